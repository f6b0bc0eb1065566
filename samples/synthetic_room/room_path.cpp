#include "room_path.h"

#include <algorithm>
#include <cmath>
#include <limits>

namespace vf::synth {
namespace {

constexpr double kDeg = M_PI / 180.0;
// The loop: centre, radii (it stays >= 1.1 m from every piece of furniture and 2.2 m from the
// walls, so everything in view lies between 1 and 4 m), and its rate: 370 degrees over the
// 299 intervals of the default 300 frames, so that the scan ends overlapping its start.
constexpr double kCentreX = 4.0, kCentreY = 3.0, kRadiusX = 1.2, kRadiusY = 0.8;
constexpr double kLoopRate_rad_s = 370.0 * kDeg / ((kDefaultFrames - 1) / kFrameRateHz);

}  // namespace

Intrinsics kinectIntrinsics(int width, int height) {
  Intrinsics k;
  const float s = float(width) / 640.f;
  k.width = width;
  k.height = height;
  k.fx = 525.f * s;
  k.fy = 525.f * float(height) / 480.f;
  k.cx = (319.5f + 0.5f) * s - 0.5f;
  k.cy = (239.5f + 0.5f) * float(height) / 480.f - 0.5f;
  return k;
}

double frameTimestamp(int index) { return kFirstTimestamp_s + double(index) / kFrameRateHz; }

Pose cameraPose(double t) {
  const double a = kLoopRate_rad_s * t;  // position on the loop
  const Eigen::Vector3d position(kCentreX + kRadiusX * std::cos(a), kCentreY + kRadiusY * std::sin(a),
                                 1.45 + 0.05 * std::sin(2 * a + 0.3) + 0.004 * std::sin(11.0 * t));
  // Heading: outwards from the loop's centre, swinging +-6 degrees about it; pitch 20 degrees
  // down +-4; roll +-3; each with a slower hand shake of a few tenths of a degree.
  const double yaw = a + 6 * kDeg * std::sin(2 * a) + 0.3 * kDeg * std::sin(7.0 * t + 1);
  const double pitch = 20 * kDeg + 4 * kDeg * std::sin(3 * a + 1) + 0.3 * kDeg * std::sin(9.0 * t);
  const double roll = 3 * kDeg * std::sin(2 * a + 2) + 0.3 * kDeg * std::sin(8.0 * t + 2);

  return headingPose(position, yaw, pitch, roll);
}

Pose headingPose(const Eigen::Vector3d& position, double yaw, double pitch, double roll) {
  const Eigen::Vector3d forward(std::cos(pitch) * std::cos(yaw), std::cos(pitch) * std::sin(yaw), -std::sin(pitch));
  const Eigen::Vector3d right0(std::sin(yaw), -std::cos(yaw), 0);  // horizontal
  const Eigen::Vector3d down0 = forward.cross(right0);
  const Eigen::Vector3d right = std::cos(roll) * right0 + std::sin(roll) * down0;
  const Eigen::Vector3d down = forward.cross(right);
  Pose pose = Pose::Identity();
  pose.linear().col(0) = right;
  pose.linear().col(1) = down;
  pose.linear().col(2) = forward;
  pose.translation() = position;
  return pose;
}

Trajectory cameraPath(int frames) {
  Trajectory path;
  for (int i = 0; i < frames; ++i)
    path.push_back({frameTimestamp(i), cameraPose(frameTimestamp(i) - kFirstTimestamp_s)});
  return path;
}

PathStats pathStats(const Trajectory& path) {
  PathStats s;
  if (path.empty()) return s;
  s.min_height_m = std::numeric_limits<double>::infinity();
  s.max_height_m = -s.min_height_m;
  double heading_prev = 0, turn = 0;
  for (size_t i = 0; i < path.size(); ++i) {
    const Pose& p = path[i].T_world_cam;
    s.min_height_m = std::min(s.min_height_m, p.translation().z());
    s.max_height_m = std::max(s.max_height_m, p.translation().z());
    const Eigen::Vector3d f = p.linear().col(2);
    const double heading = std::atan2(f.y(), f.x());
    if (i > 0) {
      const Pose& q = path[i - 1].T_world_cam;
      const double dt = path[i].timestamp - path[i - 1].timestamp;
      const double step = (p.translation() - q.translation()).norm();
      const double angle = Eigen::AngleAxisd(q.linear().transpose() * p.linear()).angle();
      s.length_m += step;
      if (dt > 0) {
        s.max_speed_m_s = std::max(s.max_speed_m_s, step / dt);
        s.max_turn_rate_deg_s = std::max(s.max_turn_rate_deg_s, angle / kDeg / dt);
      }
      turn += std::remainder(heading - heading_prev, 2 * M_PI);
    }
    heading_prev = heading;
  }
  s.turn_deg = turn / kDeg;
  return s;
}

}  // namespace vf::synth
