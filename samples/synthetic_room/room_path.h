#pragma once
// The hand-held camera of the synthetic room scan: a Kinect v1 (640x480, f = 525 px) carried at
// chest height around the middle of the room at 30 Hz, looking outwards and down at the
// furniture along the walls, so that it turns a full circle (370 degrees in 300 frames) while it
// walks, with slow height, pitch and roll wobble and a little hand shake on top.
#include "core/intrinsics.h"
#include "core/pose.h"

namespace vf::synth {

constexpr double kFrameRateHz = 30.0;
constexpr double kFirstTimestamp_s = 1.0;
constexpr int kDefaultFrames = 300;

// Kinect v1 colour-registered depth: fx = fy = 525, cx = 319.5, cy = 239.5 at 640x480, scaled
// for other sizes (tests render small images of the same view).
Intrinsics kinectIntrinsics(int width = 640, int height = 480);

// T_world_cam (camera x right, y down, z forward; world z up) at time t_s after the first frame.
Pose cameraPose(double t_s);

// T_world_cam of a camera at `position` looking along heading `yaw` (radians from world +x
// towards +y), `pitch` below the horizon, rolled by `roll` about its optical axis.
Pose headingPose(const Eigen::Vector3d& position, double yaw, double pitch, double roll);

// The poses of frames 0..frames-1, 1/30 s apart from kFirstTimestamp_s.
Trajectory cameraPath(int frames);
double frameTimestamp(int index);

struct PathStats {
  double length_m = 0;              // sum of the steps between frames
  double turn_deg = 0;              // heading change, unwrapped, first frame to last
  double max_speed_m_s = 0;         // largest step / frame interval
  double max_turn_rate_deg_s = 0;   // largest rotation between frames / frame interval
  double min_height_m = 0, max_height_m = 0;
};
PathStats pathStats(const Trajectory& path);

}  // namespace vf::synth
