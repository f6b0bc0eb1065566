// vdbfuse-view: look at a scene document. Interactive by default; --screenshot renders offscreen
// to a PNG or JPEG (by extension) and exits. Exit codes: 0 fine, 1 a vf::Error (message on stderr), 2 unexpected.
#include <CLI/CLI.hpp>

#include <chrono>
#include <cstdio>
#include <exception>

#include "app/output_policy.h"
#include "app/run_control.h"
#include "app/usage_errors.h"
#include "core/error.h"
#include "core/version.h"
#include "viewer/display_check.h"
#include "viewer/scene_content.h"
#include "viewer/scene_view.h"
#include "viewer/view_options.h"

namespace {

using namespace vf;
using namespace vf::viewer;

double secondsSince(std::chrono::steady_clock::time_point t0) {
  return std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count();
}

int runViewer(const ViewOptions& o, bool force) {
  const bool offscreen = !o.screenshot_path.empty();
  if (offscreen) {
    pictureFormatFromPath(o.screenshot_path);  // a wrong extension fails before the work
    app::OutputPolicy outputs(force);
    outputs.input(o.scene_path);
    if (!o.trajectory_path.empty()) outputs.input(o.trajectory_path);
    outputs.file(o.screenshot_path, "--screenshot");
  }
  requireDisplay(offscreen);  // before the scene is read: fail in a second, not after meshing
  const auto t0 = std::chrono::steady_clock::now();
  // --no-trajectory hides the path; a trajectory camera still needs the poses.
  const bool need_poses = o.show_trajectory || o.camera.preset == CameraPreset::kTrajectory;
  SceneContent content = loadSceneContent(o.scene_path, o.trajectory_path, need_poses, o.min_weight);
  for (const std::string& n : content.notices) std::fprintf(stderr, "vdbfuse-view: note: %s\n", n.c_str());
  if (content.triangles == 0 && !o.slice.enabled)
    throw Error(o.scene_path + ": no surface in the scene (" + std::to_string(content.summary.active_voxels) +
                " observed voxels but no zero crossing" + (o.min_weight > 0 ? " above --min-weight" : "") +
                "); --slice z:VALUE shows the grids anyway");
  SceneView view(content, o, offscreen);
  for (const std::string& n : view.notices()) std::fprintf(stderr, "vdbfuse-view: note: %s\n", n.c_str());
  if (offscreen) {
    view.saveScreenshot(o.screenshot_path);
    std::printf("wrote %s (%dx%d): read %.2f s, mesh %.2f s, split %.2f s, actors %.2f s, render %.2f s, total %.2f s\n",
                o.screenshot_path.c_str(), o.width, o.height, content.read_s, content.mesh_s, content.split_s,
                view.buildSeconds(), view.firstRenderSeconds(), secondsSince(t0));
    std::printf("%s\n", view.cameraReport().c_str());
    return 0;
  }
  std::printf("%s: %zu triangles, %zu classes; read %.2f s, mesh %.2f s, split %.2f s, actors %.2f s\n",
              o.scene_path.c_str(), content.triangles, content.rows.size(), content.read_s, content.mesh_s,
              content.split_s, view.buildSeconds());
  std::printf("press h in the window for the keys\n");
  std::fflush(stdout);
  view.run();
  return 0;
}

}  // namespace

int main(int argc, char** argv) {
  app::startSignalThread();  // before VTK starts threads (app/run_control.h)
  ViewOptions o;
  bool force = false;
  std::string size, camera = "front", color = "rgb", slice, slice_grid = "tsdf";
  bool no_trajectory = false;
  CLI::App app{"vdbfuse-view " VDBFUSE_VERSION_STRING ": look at a vdbfuse scene (.vdb): surface by RGB or class, "
               "camera trajectory, TSDF / weight slices. Press h in the window for the keys."};
  app.set_version_flag("--version", VDBFUSE_VERSION_STRING);
  app.add_option("scene", o.scene_path, "scene document (.vdb)")->required();
  app.add_option("--trajectory", o.trajectory_path, "TUM trajectory to draw (default: the scene's stem + .txt)");
  app.add_flag("--no-trajectory", no_trajectory, "do not draw the trajectory");
  app.add_flag("--frusta", o.show_frusta, "draw camera frusta along the trajectory, spaced by the camera's motion "
                                          "(key k toggles them)");
  app.add_option("--frustum-every", o.frustum_every, "a camera frustum every N poses (implies --frusta)")
      ->check(vf::app::atLeast(1));
  bool no_surface = false;
  app.add_flag("--no-surface", no_surface, "hide the surface (key m toggles it): a slice shows unobstructed");
  app.add_option("--screenshot", o.screenshot_path, "render offscreen to this .png or .jpg and exit (needs X: xvfb-run -a)");
  app.add_flag("-f,--force", force, "overwrite an existing --screenshot file");
  app.add_option("--size", size, "window / picture size WIDTHxHEIGHT (default 1280x720)");
  CLI::Option* camera_option = app.add_option(
      "--camera", camera, "front | top | side | trajectory:N (pose N of the trajectory); front looks the way the "
                          "first camera did, level (the scene's up is the picture's up), side is turned 90 degrees "
                          "about up, top looks down; default: front, or facing the slice");
  app.add_option("--color", color, "surface colors: fused rgb or class colors")
      ->check(CLI::IsMember({"rgb", "class"}))
      ->capture_default_str();
  app.add_option("--hide-classes", o.hide_classes, "classes to hide at start (names or ids)")->delimiter(',');
  app.add_option("--slice", slice, "show a slice: height=METRES, a floor plan that high above the floor (the "
                                   "surface above it is cut away), e.g. height=1.0; or x|y|z:VALUE across a world "
                                   "axis, metres, e.g. z:1.5");
  app.add_option("--slice-grid", slice_grid, "grid the slice shows")
      ->check(CLI::IsMember({"tsdf", "weight"}))
      ->capture_default_str();
  app.add_option("--min-weight", o.min_weight, "treat voxels observed fewer times as unobserved")->capture_default_str();
  vf::app::requireFiniteNumbers(app);
  try {
    app.parse(argc, argv);
    if (!size.empty()) parseWindowSize(size, o.width, o.height);
    o.camera = parseCameraSpec(camera);
    o.camera_given = camera_option->count() > 0;
    o.color_by_class = color == "class";
    if (!slice.empty()) o.slice = parseSliceSpec(slice);
    o.slice.grid = slice_grid == "weight" ? SliceGrid::kWeight : SliceGrid::kTsdf;
    o.show_trajectory = !no_trajectory;
    o.show_surface = !no_surface;
    return runViewer(o, force);
  } catch (const CLI::ParseError& e) {
    return vf::app::reportParseError(app, e, "vdbfuse-view");
  } catch (const Error& e) {
    std::fprintf(stderr, "vdbfuse-view: error: %s\n", e.what());
    return 1;
  } catch (const std::exception& e) {
    std::fprintf(stderr, "vdbfuse-view: internal error: %s\n", e.what());
    return 2;
  }
}
