// Issue 37, item 4: the report of a real run names the depth that --max-depth-m left out and
// keeps the engineering table behind --verbose. Through the vdbfuse binary on the TUM sample.
#include <gtest/gtest.h>

#include <cstdlib>
#include <regex>

#include "reliability/cli_harness.h"
#include "test_data.h"

namespace vf {
namespace {

using test::runVdbfuse;

TEST(ReconstructReport, NamesTheDepthBeyondTheRangeAndSuggestsOne) {
  const std::string dir = test::tempDir("report_range");
  // fr1/xyz looks at a desk 0.6-1.5 m away with a wall and a room behind it up to ~4 m.
  const test::CliRun run = runVdbfuse({"reconstruct", test::dataPath("tum_fr1_xyz_head100"), "-o", dir + "/scene.vdb",
                                       "-q", "--max-depth-m", "1.2", "--loop-closure", "off"});
  ASSERT_EQ(run.status, 0) << run.output;
  std::smatch m;
  ASSERT_TRUE(std::regex_search(run.output, m,
                                std::regex(R"(depth: ([0-9.]+) % of the valid readings lie beyond --max-depth-m 1\.2 m)")))
      << run.output;
  const double share = std::stod(m[1]);
  EXPECT_GT(share, 10.0) << run.output;
  EXPECT_LT(share, 90.0) << run.output;
  ASSERT_TRUE(std::regex_search(run.output, m, std::regex(R"(--max-depth-m ([0-9.]+) would fuse 99 %)"))) << run.output;
  EXPECT_GT(std::stod(m[1]), 1.2) << run.output;
  // The short report: the frames and the time, no stage table.
  EXPECT_TRUE(std::regex_search(run.output, std::regex(R"(\n100 frames in [0-9.]+ s \([0-9.]+ frames/s including I/O\))")))
      << run.output;
  EXPECT_EQ(run.output.find("median ms"), std::string::npos) << run.output;
}

TEST(ReconstructReport, VerboseAddsTheStageTable) {
  const std::string dir = test::tempDir("report_verbose");
  const test::CliRun run = runVdbfuse({"reconstruct", test::dataPath("tum_fr3_teddy_head60"), "-o", dir + "/scene.vdb",
                                       "-q", "--verbose"});
  ASSERT_EQ(run.status, 0) << run.output;
  EXPECT_NE(run.output.find("median ms"), std::string::npos) << run.output;
  EXPECT_NE(run.output.find("bricks fused per frame: median"), std::string::npos) << run.output;
}

}  // namespace
}  // namespace vf
