#pragma once
// The VTK inspector of one scene: per-class surface actors, trajectory, slice with color bar,
// class panel, help and status overlays, camera presets; interactive or offscreen to a PNG.
// No VTK in this header: main.cpp and tests include it without VTK's include paths.
#include <memory>
#include <string>
#include <vector>

#include "viewer/scene_content.h"
#include "viewer/view_options.h"

namespace vf::viewer {

class SceneView {
 public:
  // Builds every actor. Throws vf::Error for options the scene cannot satisfy (an unknown
  // --hide-classes name, a slice outside the scene, trajectory:N without such a pose).
  // offscreen: no window appears (still needs an X server, see display_check.h).
  SceneView(SceneContent& content, const ViewOptions& options, bool offscreen);
  ~SceneView();
  SceneView(const SceneView&) = delete;
  SceneView& operator=(const SceneView&) = delete;

  // Renders and writes a PNG atomically (temp file + rename).
  void saveScreenshot(const std::string& path);
  // Opens the window and runs until it is closed or q / Escape.
  void run();
  // Seconds spent building actors and rendering the first frame (after saveScreenshot / run).
  double buildSeconds() const;
  double firstRenderSeconds() const;
  // The camera as VTK holds it (direction of projection, orthogonalised view-up, world
  // coordinates), the scene's up and floor, and the slice's plane normal when one is shown:
  // one or two lines, printed with --screenshot (tests measure the view's level from them).
  std::string cameraReport() const;
  // Things the user should know (class coloring unavailable, ...), in order.
  const std::vector<std::string>& notices() const;

 private:
  struct Impl;
  std::unique_ptr<Impl> impl_;
};

}  // namespace vf::viewer
