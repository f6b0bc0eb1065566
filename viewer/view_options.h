#pragma once
// What vdbfuse-view was asked to show, and the parsers of its compact option values
// ("z:0.5", "1280x720", "trajectory:12"). Plain C++: shared by the VTK view and its tests.
#include <string>
#include <vector>

#include "core/intrinsics.h"

namespace vf::viewer {

// The world frame is the first camera's (x right, y down, z forward). front: looking along +z
// with -y up, as the first camera; top: looking down +y onto the floor with +z (into the
// scene) up; side: looking along +x with -y up; trajectory: exactly pose N's camera.
enum class CameraPreset { kFront, kTop, kSide, kTrajectory };
struct CameraSpec {
  CameraPreset preset = CameraPreset::kFront;
  int frame = 0;  // kTrajectory: pose index in the trajectory file
};

enum class SliceGrid { kTsdf, kWeight };
struct SliceSpec {
  bool enabled = false;
  int axis = 2;  // 0 = x, 1 = y, 2 = z (world axes, metres)
  float value_m = 0;
  SliceGrid grid = SliceGrid::kTsdf;
};

struct ViewOptions {
  std::string scene_path;
  std::string trajectory_path;  // empty: the scene's stem + ".txt", if present
  bool show_trajectory = true;
  int frustum_every = 0;        // 0: spaced by the camera's motion (frustum_poses.h)
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
// "x:VALUE", "y:VALUE" or "z:VALUE" (metres, world frame). Throws vf::Error naming the value.
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

// The preset that looks straight at a slice across `axis` (x: side, y: top, z: front).
CameraPreset cameraFacingAxis(int axis);

}  // namespace vf::viewer
