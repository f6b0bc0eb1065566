#pragma once
// After the first pass: the keyframes' loops found and verified (slam/loop_closure.h), a lone loop
// that would move the map dropped (slam/loop_support.h), the pose graph optimised
// (slam/pose_graph.h), and every posed frame moved with the keyframe it was tracked after (its
// pose relative to that keyframe is what tracking measured and stays).
#include <vector>

#include "core/pose.h"
#include "slam/keyframes.h"
#include "slam/loop_closure.h"
#include "slam/loop_support.h"
#include "slam/pose_graph.h"
#include "slam/prior_held.h"

namespace vf::slam {

struct GlobalParams {
  bool loop_closure = true;
  // The frames are fused again only when the optimisation moves some part of a view (its camera,
  // or the point 2 m in front of it) by at least this much: less cannot double a surface, and a
  // second pass costs about half the first.
  double min_correction_m = 0.005;
  // When fewer than `min_disagreeing_loops` loops disagree with the first pass's poses by more
  // than `loops_agree_chi` of their standard deviations, the poses stand as they are: drift
  // shows in several loops at once, while one alignment off by a little is the sensor's (TUM
  // fr1/xyz's 798 frames: 279 loops, the median at 0.60, one at 2.23; optimising for that one
  // moved frames up to 1.8 cm and the ATE went from 0.79 to 0.87 cm). A loop that disagrees
  // must also be confirmed by a loop next to it (slam/loop_support.h).
  double loops_agree_chi = 2.0;
  int min_disagreeing_loops = 3;
  // A map started after a loss (slam/map_joining.h) is moved onto the older ones only when at
  // least this many loops agree on where it lies.
  int min_joining_loops = 2;
  // A later map whose surfaces face at least this many degrees away from where the older maps'
  // floor and walls face is also searched for turned to face as they do (slam/map_orientation.h):
  // the ring corridor cut at walk frame 600 turned 14.1 degrees (its placement was 13.2 off),
  // 32 loops joined it where none had, ATE 59.0 -> 3.1 cm. 0: searched for only as placed.
  double min_map_turn_deg = 5.0;
  LoopParams loops;
  LoopSupportParams support;  // a loop that would move the map within one must be seen twice
  PoseGraphParams graph;
};

struct GlobalReport {
  int keyframes = 0;
  int candidates = 0;         // keyframe pairs checked
  int loops_found = 0;        // whose depth aligned
  int loops_accepted = 0;     // that the optimised graph agrees with
  double largest_correction_m = 0, median_correction_m = 0;  // how far the frames' views moved
  bool moved_enough = false;  // the frames were moved (and are fused again)
  int maps = 1;               // the tracker's maps (slam/tracker.h: a new one after a long loss)
  int maps_joined = 0;        // later maps placed on the older ones by loops
  int maps_turned = 0;        // later maps also searched for turned (GlobalParams::min_map_turn_deg)
  // Bricks the first pass restarted where it came back (fusion/params.h restart_stale_bricks):
  // when > 0 every frame is fused again, moved or not.
  int64_t bricks_restarted = 0;
  bool moved() const { return moved_enough; }
};

// poses[k] was tracked after keyframe anchors[k] (-1: before any keyframe; such a pose stays);
// prior_held: where tracking leaned on the motion prior (its odometry is trusted less there).
// Moves the keyframes' poses in `keyframes` and returns the frames' poses; unchanged when no loop
// holds. Several maps (keyframes' `map`) are joined by their loops first (slam/map_joining.h).
std::vector<Pose> optimiseTrajectory(KeyframeStore& keyframes, const std::vector<Pose>& poses,
                                     const std::vector<int>& anchors, const std::vector<PriorHeldStretch>& prior_held,
                                     const GlobalParams& params, GlobalReport* report);

}  // namespace vf::slam
