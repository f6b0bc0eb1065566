// The tracker's decisions on real frames (slam/tracker.h): a frame from another place is held
// back and not fused, tracking comes back after it through relocalisation and a probation, a
// run that starts with blank frames starts its map at the first frame with depth, a camera lost
// where the map cannot find it starts a new one, and two views of different places are not taken
// for a loop.
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

// Teddy frames 0-9, then the kitchen's frames as if the camera, lost, had walked on into a room
// the map has never seen (25 frames a second after the teddy's last).
struct WalkedOn {
  int lost_before_new_map = 0;  // kitchen frames lost before one started a new map (-1: none did)
  int tracked_after = 0;        // kitchen frames fused after it
};
WalkedOn walkOnIntoAnotherRoom(const TrackerParams& tracking) {
  const TumDataset teddy(test::dataPath("tum_fr3_teddy_head60"));
  const FrameListSource kitchen(readSevenScenes(test::dataPath("7scenes_redkitchen_head100")));
  Pipeline pipeline(params(), teddy.depthIntrinsics(), Device::Cpu);
  Tracker tracker(pipeline, PoseSource::Icp, tracking);
  double t = 0;
  for (int i = 0; i < 10; ++i) {
    const RgbdFrame frame = teddy.load(i);
    t = frame.timestamp;
    EXPECT_TRUE(tracker.process(frame).result.integrated) << "teddy frame " << i;
  }
  WalkedOn out{-1, 0};
  for (int k = 0; k < 20; ++k) {
    RgbdFrame frame = kitchen.load(k);
    frame.index = 10 + k;
    frame.timestamp = t + 0.04 * (k + 1);
    const Tracker::Step step = tracker.process(frame);
    if (step.new_map) {
      EXPECT_EQ(out.lost_before_new_map, -1) << "a second new map at kitchen frame " << k;
      out.lost_before_new_map = k;
      // The teddy's volume was dropped: this frame's bricks are all there is.
      EXPECT_EQ(pipeline.brickCount(), step.result.bricks_fused);
      EXPECT_EQ(tracker.keyframes()[tracker.keyframes().size() - 1].frame_index, frame.index);
    } else if (out.lost_before_new_map < 0) {
      EXPECT_FALSE(step.result.tracked) << "kitchen frame " << k << " relocalised in the teddy's room";
    } else {
      out.tracked_after += step.result.integrated ? 1 : 0;
    }
  }
  for (int i = 0; i < tracker.keyframes().size(); ++i)
    EXPECT_EQ(tracker.keyframes()[i].map, tracker.keyframes()[i].frame_index < 10 ? 0 : 1) << "keyframe " << i;
  EXPECT_EQ(tracker.maps(), out.lost_before_new_map >= 0 ? 2 : 1);
  return out;
}

TEST(Tracker, ACameraLostWhereTheMapCannotFindItStartsANewMap) {
  VF_REQUIRE_DATA(teddy_dir, "tum_fr3_teddy_head60");
  VF_REQUIRE_DATA(kitchen_dir, "7scenes_redkitchen_head100");
  const WalkedOn walked = walkOnIntoAnotherRoom(TrackerParams());
  // Kitchen frame 0 is lost tracking; frames 1-8 (0.08-0.36 s) search the teddy's map, and frame
  // 9, 0.32 s after the first search (new_map_after_s 0.3), starts the new map; the rest track in it.
  EXPECT_EQ(walked.lost_before_new_map, 9);
  EXPECT_EQ(walked.tracked_after, 20 - 10);
  TrackerParams never;
  never.new_map_after_s = 0;
  const WalkedOn searched = walkOnIntoAnotherRoom(never);
  EXPECT_EQ(searched.lost_before_new_map, -1);
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
