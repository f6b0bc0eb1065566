// Loops judged before the pose graph (slam/loop_support.h): on a walk round a square whose
// tracking drifted a metre, the loops of the return, each confirmed by its neighbours, stand; a
// lone loop that would move the map is dropped; a lone loop that agrees with the tracked poses
// moves nothing and stands; a look-alike seen twice at one offset stands too (the limit of the
// rule: the pose graph's switching is left for it).
#include <gtest/gtest.h>

#include <cmath>

#include "slam/loop_support.h"
#include "square_walk.h"

namespace vf::slam {
namespace {

using test::poseAt;
using test::squareWalk;

struct Walk {
  std::vector<Pose> truth, tracked;
  KeyframeStore keyframes;
};

// Tracking that turned 0.5 degree too far at every keyframe: the end lands about a metre from
// the start. One keyframe every 10 frames, all in map 0.
Walk driftingWalk() {
  Walk w;
  w.truth = squareWalk();
  w.tracked.push_back(w.truth[0]);
  for (size_t i = 0; i + 1 < w.truth.size(); ++i)
    w.tracked.push_back(w.tracked.back() * (w.truth[i].inverse() * w.truth[i + 1]) * poseAt(0, 0, 0.5));
  for (size_t i = 0; i < w.truth.size(); ++i) {
    Keyframe k;
    k.frame_index = int(10 * i);
    k.T_world_cam = w.tracked[i];
    w.keyframes.add(std::move(k));
  }
  return w;
}

// A loop measured as `measured` from keyframe `from` to `to`, at 2 cm and 1 degree.
PoseGraphEdge loop(int from, int to, const Pose& measured) {
  PoseGraphEdge e;
  e.from = from;
  e.to = to;
  e.T_from_to = measured;
  const double r = 1.0 * M_PI / 180.0;
  e.information.setZero();
  e.information.diagonal() << 1 / (r * r), 1 / (r * r), 1 / (r * r), 2500, 2500, 2500;
  e.loop = true;
  return e;
}

// As GlobalParams::loops_agree_chi: a loop within two of its deviations of the tracking moves nothing.
constexpr double kAgreeChi = 2.0;

PoseGraphEdge trueLoop(const Walk& w, int from, int to) {
  return loop(from, to, w.truth[size_t(from)].inverse() * w.truth[size_t(to)]);
}

// The tracked relative pose, then moved by `offset` in the newer keyframe's frame.
PoseGraphEdge trackedLoop(const Walk& w, int from, int to, const Pose& offset) {
  return loop(from, to, w.tracked[size_t(from)].inverse() * w.tracked[size_t(to)] * offset);
}

Pose slid(double metres) {
  Pose p = Pose::Identity();
  p.translation().z() = metres;
  return p;
}

TEST(LoopSupport, ALoneLoopThatWouldMoveTheMapIsDroppedWhileTheReturnsConfirmedLoopsStand) {
  const Walk w = driftingWalk();
  const std::vector<PoseGraphEdge> loops{
      trueLoop(w, 0, 39), trueLoop(w, 1, 39), trueLoop(w, 0, 38),  // the return, a metre from the tracking
      trackedLoop(w, 5, 15, slid(0.6)),                            // a look-alike 60 cm along the walk
      trackedLoop(w, 20, 30, slid(0.002)),                         // agrees with the tracking
  };
  // The return's loops do disagree with the tracked poses: they need (and have) support.
  EXPECT_GT(edgeChi(loops[0], w.tracked), 10.0);
  EXPECT_GT(edgeChi(loops[3], w.tracked), 10.0);
  const std::vector<bool> kept = corroboratedLoops(w.keyframes, w.tracked, loops, kAgreeChi, LoopSupportParams());
  EXPECT_EQ(kept, (std::vector<bool>{true, true, true, false, true}));
}

TEST(LoopSupport, ALookAlikeSeenTwiceAtOneOffsetStands) {
  const Walk w = driftingWalk();
  const std::vector<PoseGraphEdge> loops{trackedLoop(w, 5, 15, slid(0.6)), trackedLoop(w, 6, 16, slid(0.6))};
  EXPECT_EQ(corroboratedLoops(w.keyframes, w.tracked, loops, kAgreeChi, LoopSupportParams()), (std::vector<bool>{true, true}));
  // At offsets 30 cm apart they do not confirm each other.
  const std::vector<PoseGraphEdge> apart{trackedLoop(w, 5, 15, slid(0.6)), trackedLoop(w, 6, 16, slid(0.3))};
  EXPECT_EQ(corroboratedLoops(w.keyframes, w.tracked, apart, kAgreeChi, LoopSupportParams()), (std::vector<bool>{false, false}));
}

TEST(LoopSupport, LoopsBetweenMapsAreLeftToTheMapJoining) {
  Walk w = driftingWalk();
  for (int i = 20; i < w.keyframes.size(); ++i) w.keyframes[i].map = 1;
  const std::vector<PoseGraphEdge> loops{trackedLoop(w, 5, 25, slid(0.6))};
  EXPECT_EQ(corroboratedLoops(w.keyframes, w.tracked, loops, kAgreeChi, LoopSupportParams()), (std::vector<bool>{true}));
}

}  // namespace
}  // namespace vf::slam
