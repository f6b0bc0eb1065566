#pragma once
// What vdbfuse-view was asked to show, and the parsers of its compact option values
// ("z:0.5", "1280x720", "trajectory:12"). Plain C++: shared by the VTK view and its tests.
#include <string>
#include <vector>

#include "core/intrinsics.h"
#include "core/math.h"

namespace vf::viewer {

// Presets in the scene's level frame (viewer/level_frame.h: up against gravity, forward the
// first camera's heading): front looks the way the first camera did, level; side is turned 90
// degrees about up; top looks down along -up with forward at the top; trajectory: exactly
// pose N's camera.
enum class CameraPreset { kFront, kTop, kSide, kTrajectory };
struct CameraSpec {
  CameraPreset preset = CameraPreset::kFront;
  int frame = 0;  // kTrajectory: pose index in the trajectory file
};

enum class SliceGrid { kTsdf, kWeight };
struct SliceSpec {
  bool enabled = false;
  // A floor plan: the horizontal plane value_m metres above the floor (level_frame.h). Else a
  // plane across a world axis at world coordinate value_m.
  bool level = false;
  int axis = 2;  // 0 = x, 1 = y, 2 = z (world axes, metres)
  float value_m = 0;
  SliceGrid grid = SliceGrid::kTsdf;
};

struct ViewOptions {
  std::string scene_path;
  std::string trajectory_path;  // empty: the scene's stem + ".txt", if present
  bool show_trajectory = true;
  bool show_frusta = false;     // camera frusta along the path (off: they hid the room)
  int frustum_every = 0;        // 0: spaced by the camera's motion (frustum_poses.h)
  bool show_surface = true;
  std::string screenshot_path;  // non-empty: render offscreen to this PNG / JPEG and exit
  int width = 1280, height = 720;
  CameraSpec camera;
  bool camera_given = false;  // false: front, or facing the slice when there is one
  bool color_by_class = false;
  std::vector<std::string> hide_classes;  // names or ids
  SliceSpec slice;
  float min_weight = 0;
};

// "front", "top", "side" or "trajectory:N". Throws vf::Error naming the value.
CameraSpec parseCameraSpec(const std::string& text);
// "height=VALUE" (or height:VALUE; metres above the floor: a floor plan), or "x:VALUE",
// "y:VALUE", "z:VALUE" (metres, world frame). Throws vf::Error naming the value.
SliceSpec parseSliceSpec(const std::string& text);
// "WIDTHxHEIGHT", each 16..16384. Throws vf::Error naming the value.
void parseWindowSize(const std::string& text, int& width, int& height);

// The trajectory written beside a scene: same folder and stem, extension ".txt".
std::string defaultTrajectoryPath(const std::string& scene_path);
// A file beside the scene: <folder>/<stem><suffix> (e.g. "_visible.ply").
std::string besideScene(const std::string& scene_path, const std::string& suffix);

const char* axisName(int axis);  // "x", "y", "z"

// --screenshot's format by its extension (.png, .jpg or .jpeg, any case); throws vf::Error
// naming the path for anything else, before any work is done.
enum class PictureFormat { kPng, kJpeg };
PictureFormat pictureFormatFromPath(const std::string& path);

// What a recorded camera saw: the vertical field of view and width / height of the scene's
// depth camera (SceneMetadata::depth_intrinsics), or a Kinect's (kTrajectoryFovYDeg, 4:3) for a
// scene that does not record it.
struct FrameCamera {
  double fov_y_deg = 0, aspect = 0;
};
FrameCamera frameCamera(const Intrinsics& depth_intrinsics);

// The preset that looks at a slice: top for a floor plan; for a world axis the preset whose
// direction is nearest to the axis in `frame_up` / `frame_forward`'s level frame.
CameraPreset cameraFacingSlice(const SliceSpec& slice, Vec3f frame_up, Vec3f frame_forward);

}  // namespace vf::viewer
