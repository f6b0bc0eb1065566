// The whole ring corridor walk through a Reconstruction with its default options (issue 36,
// acceptance 1, in memory instead of written to PNG and read back). The tracker drifts round the
// 32 m loop, the camera comes back to its start after frame 1037, the loop closure finds where,
// optimises the poses and fuses the frames again. Here the odometry is off by 8.85 cm (ATE), the
// optimised poses by 1.35 (9 loops, all holding; 160 s on two cores). From the same walk written
// to PNG and read back (scripts/tracking_judge.sh) 8.06 and 1.49 cm: how far a slide along a
// plain corridor goes follows the noise. At 320x240 the walk is lost at its hard stretch (frames
// 540-600, a 40 deg look at a plain wall) and goes on in a new map (scripts/tracking_judge.sh:
// 14.3 cm, 3 of 5 loops): no test of the loop closure there.
// And a walk with a gap, carried on in a new map.
#include <gtest/gtest.h>

#include "io/trajectory_metrics.h"
#include "room_source.h"
#include "slam/reconstruction.h"

namespace vf::synth {
namespace {

TEST(CorridorLoopClosure, AWalkRoundTheCorridorEndsOnItsStartAndTheLoopCorrectsTheDrift) {
  RoomScanOptions scan = scanDefaults(Scene::kCorridor);
  const RoomScanSource source(scan);
  ReconstructionOptions options;
  options.device = Device::Cpu;
  Reconstruction run(source, options);
  ASSERT_EQ(run.run({}), Reconstruction::Outcome::Finished);

  const Trajectory truth = source.groundTruth();
  ASSERT_TRUE(run.globalReport().moved()) << "the loop closure left the poses as they were";
  const double odometry_cm = computeAte(run.odometry(), truth).rmse_m * 100;
  const double optimised_cm = computeAte(run.trajectory(), truth).rmse_m * 100;
  EXPECT_GT(odometry_cm, 5.0) << "the walk no longer drifts: the test no longer tests the loop closure";
  EXPECT_LT(optimised_cm, 3.0);
  EXPECT_LT(optimised_cm, 0.3 * odometry_cm);
  EXPECT_GE(run.globalReport().loops_found, 1);
  EXPECT_EQ(run.globalReport().loops_accepted, run.globalReport().loops_found);
  EXPECT_GE(int(run.trajectory().size()), source.size() - 5) << "frames lost on the way";
}

// The same walk with frames 600-644 cut out (1.5 s down the far leg): the camera comes back where
// the map has never been, and no place within its reach is the right one. The tracker starts a
// new map there and poses the rest of the walk in it. Written to PNG and read back
// (scripts/corridor_scan_eval.sh -- --gap 600:45) the walk's return joins the new map to the
// first by 32 loops: 3.1 cm (3.8 m before new maps, relocalised at a look-alike door 1.5 m off;
// its new map placed 13 degrees off, turned 14 for the loop search).
// Here, in memory, the new map starts where the walk's median pace over its last second led and
// a placement is judged less strictly than a relocalisation (slam/recent_motion.h,
// TrackerParams::new_map_min_covered_match); the loop search also looks from it turned to face
// as the first map's floor and walls do (slam/map_orientation.h): 25 loops join
// it and the walk ends 3.1 cm ATE, 1143 of 1155 frames posed. Searched for only as placed, 3
// loops joined it (3.2 cm), or none (59 cm, as the same walk read back from PNG did, 2026-12-07).
// Before the median pace, it started 25-30 degrees off in heading: 59.7 cm.
// Searching the first map instead (new_map_after_s 0, the tracker before new maps): 363 cm,
// 1075 posed, relocalised at a look-alike place.
TEST(CorridorLoopClosure, AfterAGapTheWalkGoesOnInANewMap) {
  RoomScanOptions scan = scanDefaults(Scene::kCorridor);
  scan.gaps = {{600, 45}};
  const RoomScanSource source(scan);
  ReconstructionOptions options;
  options.device = Device::Cpu;
  Reconstruction run(source, options);
  ASSERT_EQ(run.run({}), Reconstruction::Outcome::Finished);

  EXPECT_EQ(run.tracker().maps(), 2);
  EXPECT_EQ(run.globalReport().maps_turned, 1) << "the new map was searched for only as placed";
  EXPECT_EQ(run.globalReport().maps_joined, 1) << run.globalReport().loops_found << " loops found";
  EXPECT_GE(run.globalReport().loops_accepted, 10) << "a join that rests on a few loops is a draw";
  const double ate_cm = computeAte(run.trajectory(), source.groundTruth()).rmse_m * 100;
  EXPECT_LT(ate_cm, 10.0);
  EXPECT_GE(int(run.trajectory().size()), source.size() - 15) << "frames lost on the way";
}

}  // namespace
}  // namespace vf::synth
