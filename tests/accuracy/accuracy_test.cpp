// Trajectory accuracy on the shared captures, through the commands a user runs (README):
// `vdbfuse reconstruct DATASET -o scene.vdb` with the default options, then
// `vdbfuse evaluate --trajectory scene.txt --groundtruth DATASET/groundtruth.txt`. Each bound sits
// just above the figure measured when it was set, so that a regression of a few percent shows.
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

double reconstructAndEvaluate(const std::string& sequence) {
  const std::string dataset = test::dataPath(sequence);
  const std::string dir = test::tempDir("accuracy_" + sequence);
  const test::CliRun fused = test::runVdbfuse({"reconstruct", dataset, "-o", dir + "/scene.vdb", "-q"}, 0, 1800);
  EXPECT_EQ(fused.status, 0) << fused.output;
  const test::CliRun evaluated =
      test::runVdbfuse({"evaluate", "--trajectory", dir + "/scene.txt", "--groundtruth", dataset + "/groundtruth.txt"});
  EXPECT_EQ(evaluated.status, 0) << evaluated.output;
  const double cm = ateRmseCm(evaluated.output);
  std::printf("%s: ATE RMSE %.3f cm\n%s", sequence.c_str(), cm, evaluated.output.c_str());
  return cm;
}

TEST(Accuracy, TumFr1XyzHead100AteAtMostOneCentimetre) {
  VF_REQUIRE_DATA(dataset, "tum_fr1_xyz_head100");
  const double cm = reconstructAndEvaluate("tum_fr1_xyz_head100");
  EXPECT_GT(cm, 0);
  EXPECT_LE(cm, 1.0);
}

TEST(Accuracy, TumFr3TeddyHead60AteAtMostHalfACentimetre) {
  VF_REQUIRE_DATA(dataset, "tum_fr3_teddy_head60");
  const double cm = reconstructAndEvaluate("tum_fr3_teddy_head60");
  EXPECT_GT(cm, 0);
  EXPECT_LE(cm, 0.5);
}

}  // namespace
}  // namespace vf
