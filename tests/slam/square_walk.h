#pragma once
// A walk round a 4 m square back to its start, for the pose graph's and the map joining's tests.
#include <algorithm>
#include <cmath>
#include <vector>

#include "core/pose.h"

namespace vf::slam::test {

// At (x, 0, z), turned yaw_deg about the vertical.
inline Pose poseAt(double x, double z, double yaw_deg) {
  Pose p = Pose::Identity();
  p.linear() = Eigen::AngleAxisd(yaw_deg * M_PI / 180.0, Eigen::Vector3d::UnitY()).toRotationMatrix();
  p.translation() = Eigen::Vector3d(x, 0, z);
  return p;
}

// 40 poses round a 4 m square, looking along the walk, back at the start (pose 39 beside pose 0).
inline std::vector<Pose> squareWalk() {
  std::vector<Pose> truth;
  for (int i = 0; i < 40; ++i) {
    const int side = i / 10;
    const double s = 0.4 * (i % 10);
    const double x[4] = {s, 4.0, 4.0 - s, 0.0}, z[4] = {0.0, s, 4.0, 4.0 - s};
    truth.push_back(poseAt(x[side], z[side], -90.0 * side));
  }
  return truth;
}

// The largest distance between the positions of a[i] and b[i].
inline double worstOffsetM(const std::vector<Pose>& a, const std::vector<Pose>& b) {
  double worst = 0;
  for (size_t i = 0; i < a.size(); ++i) worst = std::max(worst, (a[i].translation() - b[i].translation()).norm());
  return worst;
}

}  // namespace vf::slam::test
