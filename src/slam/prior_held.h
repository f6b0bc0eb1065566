#pragma once
// Where tracking leaned on the motion prior: stretches of frames whose views left directions of
// the pose unmeasured (a corridor seen along its length, one wall: fusion/tracking.cpp
// solveIncrement). Their poses follow the camera's own motion there and can slide along those
// directions without any check noticing; the tracker records them (slam/tracker.h), the report
// names them, and the pose graph trusts the odometry across them less (slam/loop_closure.h).
#include <string>
#include <vector>

namespace vf::slam {

struct PriorHeldStretch {
  int first_index = 0, last_index = 0;  // in the run's frame sequence
  std::string first_name, last_name;
  int directions = 0;                   // the most that any of its frames left
  int frames() const { return last_index - first_index + 1; }
};

// How many of the frames first_index + 1 .. last_index lie in one of the stretches (in frame order).
int priorHeldFramesBetween(const std::vector<PriorHeldStretch>& stretches, int first_index, int last_index);

}  // namespace vf::slam
