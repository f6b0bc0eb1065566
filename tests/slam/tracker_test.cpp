// The tracker's decisions on real frames (slam/tracker.h): a frame from another place is held
// back and not fused, tracking comes back after it through relocalisation and a probation, a
// run that starts with blank frames starts its map at the first frame with depth, and two views
// of different places are not taken for a loop.
#include <gtest/gtest.h>

#include "io/dataset_layouts.h"
#include "io/frame_list_source.h"
#include "io/tum_dataset.h"
#include "slam/loop_closure.h"
#include "slam/tracker.h"
#include "test_data.h"

namespace vf::slam {
namespace {

PipelineParams params() {
  PipelineParams p;
  p.volume.voxel_size_m = 0.01f;  // coarse: the decisions, not the detail, are under test
  return p;
}

TEST(Tracker, AFrameFromADifferentPlaceIsHeldBackAndNotFused) {
  VF_REQUIRE_DATA(teddy_dir, "tum_fr3_teddy_head60");
  VF_REQUIRE_DATA(kitchen_dir, "7scenes_redkitchen_head100");
  const TumDataset teddy(teddy_dir);
  const FrameListSource kitchen(readSevenScenes(kitchen_dir));
  Pipeline pipeline(params(), teddy.depthIntrinsics(), Device::Cpu);
  Tracker tracker(pipeline, PoseSource::Icp);
  for (int i = 0; i < 10; ++i) ASSERT_TRUE(tracker.process(teddy.load(i)).result.integrated) << "frame " << i;
  const int bricks = pipeline.brickCount();

  RgbdFrame elsewhere = kitchen.load(0);
  elsewhere.index = 10;
  const Tracker::Step held = tracker.process(elsewhere);
  EXPECT_FALSE(held.result.tracked);
  EXPECT_FALSE(held.result.integrated);
  EXPECT_NE(held.result.reason, LostReason::None);
  EXPECT_EQ(pipeline.brickCount(), bricks) << "the other place's frame was fused";
  EXPECT_EQ(tracker.state(), Tracker::State::Lost);

  // Back in the teddy's room: relocalised at once, fused again after the probation.
  const int probation = TrackerParams().probation_frames;
  for (int k = 0; k < probation; ++k) {
    const Tracker::Step step = tracker.process(teddy.load(10 + k));
    ASSERT_TRUE(step.result.tracked) << "frame " << 10 + k << ": " << step.result.lost_reason;
    const bool last = k + 1 == probation;
    EXPECT_EQ(step.result.integrated, last) << "frame " << 10 + k;
    EXPECT_EQ(step.pending, !last);
    EXPECT_EQ(step.confirm_pending, last);
  }
  EXPECT_EQ(tracker.state(), Tracker::State::Tracking);
  EXPECT_EQ(tracker.relocalisations(), 1);
}

TEST(Tracker, ARunThatStartsBlankStartsItsMapAtTheFirstFrameWithDepth) {
  VF_REQUIRE_DATA(teddy_dir, "tum_fr3_teddy_head60");
  const TumDataset teddy(teddy_dir);
  Pipeline pipeline(params(), teddy.depthIntrinsics(), Device::Cpu);
  Tracker tracker(pipeline, PoseSource::Icp);
  for (int i = 0; i < 3; ++i) {
    RgbdFrame blank = teddy.load(i);
    std::fill(blank.depth.data(), blank.depth.data() + blank.depth.width() * blank.depth.height(), 0.f);
    const Tracker::Step step = tracker.process(blank);
    EXPECT_FALSE(step.result.tracked);
    EXPECT_EQ(step.result.reason, LostReason::NoDepth);
    EXPECT_EQ(tracker.state(), Tracker::State::Starting);
  }
  const Tracker::Step first = tracker.process(teddy.load(3));
  EXPECT_TRUE(first.result.integrated);
  EXPECT_TRUE(first.result.T_world_cam.isApprox(Pose::Identity()));
  for (int i = 4; i < 12; ++i) EXPECT_TRUE(tracker.process(teddy.load(i)).result.integrated) << "frame " << i;
  // The teddy's views measure every direction: nothing left to the motion prior.
  EXPECT_TRUE(tracker.priorHeldStretches().empty());
}

TEST(LoopClosure, TwoViewsOfDifferentPlacesAreNotALoop) {
  VF_REQUIRE_DATA(teddy_dir, "tum_fr3_teddy_head60");
  VF_REQUIRE_DATA(kitchen_dir, "7scenes_redkitchen_head100");
  const TumDataset teddy(teddy_dir);
  const FrameListSource kitchen(readSevenScenes(kitchen_dir));
  // Keyframes of the two places, which a drifting odometry has put at the same pose, far apart
  // in the sequence: both candidate rules (code, place) offer the pair.
  KeyframeStore store;
  FernEncoder encoder;
  auto keyframe = [&](const RgbdFrame& frame, const Intrinsics& camera, int index) {
    Keyframe k;
    k.frame_index = index;
    k.code = encoder.encode(frame, 0.2f, 4.f);
    k.features = extractFeatures(frame, camera, 0.2f, 4.f);
    k.cloud = makeKeyframeCloud(frame.depth, camera, 0.2f, 4.f);
    return k;
  };
  store.add(keyframe(teddy.load(0), teddy.depthIntrinsics(), 0));
  store.add(keyframe(kitchen.load(0), kitchen.depthIntrinsics(), 500));
  LoopParams loops;
  loops.max_code_dissimilarity = 1.f;
  LoopStats stats;
  EXPECT_TRUE(detectLoops(store, loops, &stats).empty());
  EXPECT_EQ(stats.candidates, 1);
  // And the same place, 30 frames apart, is one.
  KeyframeStore same;
  same.add(keyframe(teddy.load(0), teddy.depthIntrinsics(), 0));
  same.add(keyframe(teddy.load(8), teddy.depthIntrinsics(), 500));
  EXPECT_EQ(detectLoops(same, loops, &stats).size(), 1u);
}

}  // namespace
}  // namespace vf::slam
