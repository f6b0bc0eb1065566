#pragma once
// Which poses of a trajectory get a frustum drawn. Plain C++ (tested without a display).
#include <cstddef>
#include <vector>

#include "core/pose.h"

namespace vf::viewer {

// every > 0: poses 0, every, 2 every, ... and the last. every == 0: spaced by motion instead, so
// that a camera that hardly moves does not pile frustums on each other: a pose gets one when its
// centre is min_step_m from the last frustum's or it has turned by 20 degrees; the first and
// last poses always do.
std::vector<size_t> frustumPoses(const Trajectory& trajectory, int every, double min_step_m);

}  // namespace vf::viewer
