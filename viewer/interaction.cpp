#include "viewer/interaction.h"

#include <vtkObjectFactory.h>
#include <vtkRenderWindowInteractor.h>

namespace vf::viewer {

vtkStandardNewMacro(ViewInteractorStyle);

void ViewInteractorStyle::OnChar() {
  vtkRenderWindowInteractor* rwi = this->Interactor;
  if (!rwi || !on_key) return;
  const char* sym = rwi->GetKeySym();
  on_key(rwi->GetKeyCode(), sym ? sym : "");
}

void ViewInteractorStyle::OnLeftButtonDown() {
  vtkRenderWindowInteractor* rwi = this->Interactor;
  if (rwi && on_click) {
    const int* pos = rwi->GetEventPosition();
    if (on_click(pos[0], pos[1])) return;
  }
  vtkInteractorStyleTrackballCamera::OnLeftButtonDown();
}

}  // namespace vf::viewer
