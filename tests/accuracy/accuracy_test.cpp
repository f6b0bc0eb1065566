// Trajectory accuracy on the shared captures, through the commands a user runs (README):
// `vdbfuse reconstruct DATASET -o scene.vdb` with the default options, then
// `vdbfuse evaluate --trajectory scene.txt --groundtruth DATASET/groundtruth.txt`. Each bound sits
// just above the figure measured when it was set, so that a regression of a few percent shows.
// The same runs also bound the bricks a frame's depth reaches (the median `reconstruct` prints),
// which the integrate and raycast cost follows: a marking that lists bricks for nothing shows.
#include <gtest/gtest.h>

#include <cstdio>
#include <sstream>

#include "reliability/cli_harness.h"
#include "test_data.h"

namespace vf {
namespace {

// ATE RMSE in cm as `evaluate` prints it ("  rmse  0.993 cm" under the "ATE" heading).
double ateRmseCm(const std::string& evaluate_output) {
  const size_t ate = evaluate_output.find("ATE");
  const size_t rmse = evaluate_output.find("rmse", ate);
  if (ate == std::string::npos || rmse == std::string::npos) return -1;
  return std::stod(evaluate_output.substr(rmse + 4));
}

// The median of "bricks fused per frame: median N, largest M" in `reconstruct`'s report; -1 if absent.
int medianBricksFused(const std::string& reconstruct_output) {
  const std::string key = "bricks fused per frame: median ";
  const size_t at = reconstruct_output.find(key);
  return at == std::string::npos ? -1 : std::stoi(reconstruct_output.substr(at + key.size()));
}

struct FusedRun {
  double ate_cm = -1;
  int median_bricks_fused = -1;
};

FusedRun reconstructAndEvaluate(const std::string& sequence, const std::vector<std::string>& options = {}) {
  const std::string dataset = test::dataPath(sequence);
  const std::string dir = test::tempDir("accuracy_" + sequence);
  std::vector<std::string> args{"reconstruct", dataset, "-o", dir + "/scene.vdb", "-q", "--verbose"};
  args.insert(args.end(), options.begin(), options.end());
  const test::CliRun fused = test::runVdbfuse(args, 0, 1800);
  EXPECT_EQ(fused.status, 0) << fused.output;
  const test::CliRun evaluated =
      test::runVdbfuse({"evaluate", "--trajectory", dir + "/scene.txt", "--groundtruth", dataset});
  EXPECT_EQ(evaluated.status, 0) << evaluated.output;
  FusedRun run;
  run.ate_cm = ateRmseCm(evaluated.output);
  run.median_bricks_fused = medianBricksFused(fused.output);
  std::printf("%s: ATE RMSE %.3f cm, %d bricks fused a frame (median)\n%s", sequence.c_str(), run.ate_cm,
              run.median_bricks_fused, evaluated.output.c_str());
  return run;
}

// Bounds on the bricks: 8 % above the 3328 (fr1) and 4557 (teddy) of the exact marking; the
// marking before it, a cube around each step of a pixel's band, gave fr1 25 % more bricks.
TEST(Accuracy, TumFr1XyzHead100AteAtMostOneCentimetre) {
  VF_REQUIRE_DATA(dataset, "tum_fr1_xyz_head100");
  const FusedRun run = reconstructAndEvaluate("tum_fr1_xyz_head100");
  EXPECT_GT(run.ate_cm, 0);
  EXPECT_LE(run.ate_cm, 1.0);
  EXPECT_GT(run.median_bricks_fused, 0) << "reconstruct no longer reports the bricks fused per frame";
  EXPECT_LE(run.median_bricks_fused, 3600);
}

TEST(Accuracy, TumFr3TeddyHead60AteAtMostHalfACentimetre) {
  VF_REQUIRE_DATA(dataset, "tum_fr3_teddy_head60");
  const FusedRun run = reconstructAndEvaluate("tum_fr3_teddy_head60");
  EXPECT_GT(run.ate_cm, 0);
  EXPECT_LE(run.ate_cm, 0.5);
  EXPECT_GT(run.median_bricks_fused, 0) << "reconstruct no longer reports the bricks fused per frame";
  EXPECT_LE(run.median_bricks_fused, 4900);
}

// 7-Scenes: the dataset's poses are KinectFusion's own, with a few glitches of their own (frame 121
// -> 122 of redkitchen jumps 3.6 cm and 1.4 degrees where the depth moved 0.6 cm; the depth of the
// two frames lines up to 2.3 mm under the estimate's motion, 7.4 mm under the dataset's), so the
// bounds sit above what any tracker that follows the depth can reach. The 500 frames walk round
// the kitchen: drift, not noise, is what they measure.
TEST(Accuracy, SevenScenesKitchenHead100AteAtMostOneCentimetre) {
  VF_REQUIRE_DATA(dataset, "7scenes_redkitchen_head100");
  const FusedRun run = reconstructAndEvaluate("7scenes_redkitchen_head100");
  EXPECT_GT(run.ate_cm, 0);
  EXPECT_LE(run.ate_cm, 1.0);
}

TEST(Accuracy, SevenScenesKitchenHead500AteAtMostThreeCentimetres) {
  VF_REQUIRE_DATA(dataset, "7scenes_redkitchen_head500");
  const FusedRun run = reconstructAndEvaluate("7scenes_redkitchen_head500");
  EXPECT_GT(run.ate_cm, 0);
  EXPECT_LE(run.ate_cm, 3.0);
}

// The iPhone capture: ICP with the dancer left out, against the phone's own (ARKit) poses, which
// are no motion capture but drift little over 200 frames. 1.50 cm when set (1.60 before the
// tracking work of 2026-12-05; 2.67 with the Kinect's depth noise model applied to the LiDAR).
TEST(Accuracy, Record3dDanceHead200WithTheDancerMaskedWithinOnePointSevenCentimetres) {
  VF_REQUIRE_DATA(dataset, "record3d_dance_head200.r3d");
  VF_REQUIRE_DATA(labels, "record3d_dance_head200_labels");
  const FusedRun run = reconstructAndEvaluate("record3d_dance_head200.r3d",
                                              {"--labels", labels, "--dynamic-classes", "person", "--voxel-size-m", "0.01"});
  EXPECT_GT(run.ate_cm, 0);
  EXPECT_LE(run.ate_cm, 1.7);
}

}  // namespace
}  // namespace vf
