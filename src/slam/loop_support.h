#pragma once
// A loop that would move the map must be seen twice. Every check on one pair of views (overlap,
// residual, surfaces that pin the translation down: slam/loop_closure.h) can pass for a
// look-alike place: a corridor's next door frame, metres along. Where the tracked poses already
// agree with a loop, it moves nothing and may stand alone; a loop that disagrees with them is
// kept only when another loop, between keyframes next to both of its ends, puts the newer end in
// the same place (as ORB-SLAM asks consecutive keyframes to confirm a loop). A real return is
// seen from several keyframes in a row; a look-alike rarely twice at one offset.
// (The ring corridor with TUM-like depth, 640x480: its first pass tracked to 2.0 cm ATE, and one
// loop from frame 847 to 960, 67 cm along the corridor from the truth, alone in that stretch,
// bent the map: 22.5 cm. The pose graph's robust loss cannot tell it: across frames the motion
// prior held, the odometry may slide along the corridor, and the graph put the 67 cm there.)
#include <vector>

#include "core/pose.h"
#include "slam/keyframes.h"
#include "slam/pose_graph.h"

namespace vf::slam {

struct LoopSupportParams {
  int neighbourhood = 3;        // supporting loops join keyframes at most this many from each end
  double agree_m = 0.10;        // and put the newer end within this distance
  double agree_deg = 3.0;       // and this angle of where the loop puts it
};

// Per loop: false for one between keyframes of one map that disagrees with `poses` by more than
// `agree_chi` of its standard deviations (edgeChi) and that no other such loop supports. Loops
// between maps are left to the map joining (slam/map_joining.h).
std::vector<bool> corroboratedLoops(const KeyframeStore& keyframes, const std::vector<Pose>& poses,
                                    const std::vector<PoseGraphEdge>& loops, double agree_chi,
                                    const LoopSupportParams& params);

}  // namespace vf::slam
