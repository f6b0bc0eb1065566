#pragma once
// The viewer's interactor style: trackball camera for the mouse, every key routed to the view
// (VTK's default keys would otherwise quit on 'e', switch to wireframe on 'w', stereo on '3'),
// and left clicks offered to the class panel before they rotate. VTK header: viewer/*.cpp only.
#include <vtkInteractorStyleTrackballCamera.h>

#include <functional>
#include <string>

namespace vf::viewer {

class ViewInteractorStyle : public vtkInteractorStyleTrackballCamera {
 public:
  static ViewInteractorStyle* New();
  vtkTypeMacro(ViewInteractorStyle, vtkInteractorStyleTrackballCamera);

  // key: the character (0 for keys without one), keysym: X key name ("Escape", "bracketleft").
  std::function<void(char key, const std::string& keysym)> on_key;
  // Display coordinates (origin bottom left); true when the click was used.
  std::function<bool(int x, int y)> on_click;

  void OnChar() override;
  void OnKeyPress() override {}
  void OnKeyRelease() override {}
  void OnLeftButtonDown() override;
};

}  // namespace vf::viewer
