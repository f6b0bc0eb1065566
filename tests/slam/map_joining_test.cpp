// Joining a run's maps (slam/map_joining.h): a map started after a long loss, placed metres off
// by the guess, is moved onto the older map where its loops agree; one loop alone, or a loop
// into a look-alike place, moves nothing.
#include <gtest/gtest.h>

#include <cmath>

#include "slam/map_joining.h"
#include "square_walk.h"

namespace vf::slam {
namespace {

using test::poseAt;
using test::worstOffsetM;

// 40 keyframes round a 4 m square back to its start; from keyframe 20 on a second map, tracked
// in a frame the guess put 1.5 m and 35 degrees off.
struct TwoMaps {
  std::vector<Pose> truth, tracked;
  KeyframeStore keyframes;
  Pose guess_error = poseAt(1.5, -0.8, 35.0);
};

TwoMaps twoMaps() {
  TwoMaps m;
  m.truth = test::squareWalk();
  for (int i = 0; i < 40; ++i) {
    Keyframe k;
    k.frame_index = 10 * i;
    k.map = i < 20 ? 0 : 1;
    k.T_world_cam = k.map == 0 ? m.truth[size_t(i)] : m.guess_error * m.truth[size_t(i)];
    m.tracked.push_back(k.T_world_cam);
    m.keyframes.add(std::move(k));
  }
  return m;
}

PoseGraphEdge loop(const std::vector<Pose>& truth, int from, int to, const Pose& error = Pose::Identity()) {
  PoseGraphEdge e;
  e.from = from;
  e.to = to;
  e.T_from_to = truth[size_t(from)].inverse() * truth[size_t(to)] * error;
  e.loop = true;
  return e;
}

TEST(MapJoining, ALaterMapIsMovedOntoTheOlderOneWhereItsLoopsAgree) {
  TwoMaps m = twoMaps();
  // Back at the start: the last keyframes see what the first ones saw.
  const std::vector<PoseGraphEdge> loops{loop(m.truth, 0, 39), loop(m.truth, 1, 39), loop(m.truth, 0, 38)};
  const JoinedMaps joined = joinMaps(m.keyframes, m.tracked, loops, 2);
  EXPECT_EQ(joined.maps, 2);
  EXPECT_EQ(joined.joined, 1);
  EXPECT_EQ(joined.keep_loop, std::vector<bool>(3, true));
  EXPECT_GT(worstOffsetM(m.tracked, m.truth), 1.0);  // what the guess was
  EXPECT_LT(worstOffsetM(joined.poses, m.truth), 1e-9);
}

TEST(MapJoining, OneLoopAloneMovesNoMap) {
  TwoMaps m = twoMaps();
  const JoinedMaps joined = joinMaps(m.keyframes, m.tracked, {loop(m.truth, 0, 39)}, 2);
  EXPECT_EQ(joined.joined, 0);
  EXPECT_EQ(joined.keep_loop, std::vector<bool>{false});  // and it is not handed to the pose graph
  EXPECT_LT(worstOffsetM(joined.poses, m.tracked), 1e-12);
}

TEST(MapJoining, ALoopIntoALookAlikePlaceIsDroppedWhereTheOthersAgree) {
  TwoMaps m = twoMaps();
  // The third says keyframe 39 is at a twin door 3 m further on.
  const std::vector<PoseGraphEdge> loops{loop(m.truth, 0, 39), loop(m.truth, 1, 38),
                                         loop(m.truth, 5, 35, poseAt(0, -3.0, 0)), loop(m.truth, 1, 39)};
  const JoinedMaps joined = joinMaps(m.keyframes, m.tracked, loops, 2);
  EXPECT_EQ(joined.joined, 1);
  EXPECT_EQ(joined.keep_loop, (std::vector<bool>{true, true, false, true}));
  EXPECT_LT(worstOffsetM(joined.poses, m.truth), 1e-9);
}

TEST(MapJoining, LoopsWithinOneMapMoveNothing) {
  TwoMaps m = twoMaps();
  for (int i = 0; i < m.keyframes.size(); ++i) m.keyframes[i].map = 0;
  const JoinedMaps joined = joinMaps(m.keyframes, m.tracked, {loop(m.truth, 0, 39), loop(m.truth, 1, 39)}, 2);
  EXPECT_EQ(joined.maps, 1);
  EXPECT_EQ(joined.joined, 0);
  EXPECT_EQ(joined.keep_loop, std::vector<bool>(2, true));
  EXPECT_LT(worstOffsetM(joined.poses, m.tracked), 1e-12);
}

}  // namespace
}  // namespace vf::slam
