#include "viewer/frustum_poses.h"

#include <cmath>

namespace vf::viewer {

std::vector<size_t> frustumPoses(const Trajectory& trajectory, int every, double min_step_m) {
  std::vector<size_t> out;
  const size_t n = trajectory.size();
  if (n == 0) return out;
  const double min_cos = std::cos(20.0 * M_PI / 180.0);
  out.push_back(0);
  for (size_t i = 1; i + 1 < n; ++i) {
    if (every > 0) {
      if (i % size_t(every) == 0) out.push_back(i);
      continue;
    }
    const Pose& last = trajectory[out.back()].T_world_cam;
    const Pose& here = trajectory[i].T_world_cam;
    const double moved = (here.translation() - last.translation()).norm();
    const double cos_turn = last.linear().col(2).dot(here.linear().col(2));  // viewing directions
    if (moved >= min_step_m || cos_turn <= min_cos) out.push_back(i);
  }
  if (n > 1) out.push_back(n - 1);
  return out;
}

}  // namespace vf::viewer
