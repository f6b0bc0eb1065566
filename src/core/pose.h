#pragma once
#include <Eigen/Geometry>
#include <cmath>
#include <vector>

#include "core/math.h"

namespace vf {

// Host-side rigid pose, double precision. T_a_b maps points of frame b into frame a.
using Pose = Eigen::Isometry3d;

inline Rigid3f toRigid3f(const Pose& pose) {
  Rigid3f out;
  const Eigen::Matrix3d r = pose.linear();
  for (int i = 0; i < 3; ++i)
    for (int j = 0; j < 3; ++j) out.r[i * 3 + j] = float(r(i, j));
  out.t = {float(pose.translation().x()), float(pose.translation().y()),
           float(pose.translation().z())};
  return out;
}

// The angle of a relative rotation (`delta`'s rotation part), in degrees.
inline double rotationDeg(const Pose& delta) { return Eigen::AngleAxisd(delta.linear()).angle() * 180.0 / M_PI; }

// Whether pose b lies within max_m of pose a, turned at most max_deg from it.
inline bool posesWithin(const Pose& a, const Pose& b, double max_m, double max_deg) {
  const Pose d = a.inverse() * b;
  return d.translation().norm() <= max_m && rotationDeg(d) <= max_deg;
}

// A timestamped camera pose, camera-to-world (TUM convention).
struct StampedPose {
  double timestamp = 0;
  Pose T_world_cam = Pose::Identity();
};
using Trajectory = std::vector<StampedPose>;

}  // namespace vf
