// Issue 37, item 4: the report of a real run names the depth that --max-depth-m left out and
// keeps the engineering table behind --verbose. Through the vdbfuse binary on the TUM sample.
#include <gtest/gtest.h>

#include <cstdlib>
#include <filesystem>
#include <regex>
#include <sstream>

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

// --frame-log: a row per frame of a real run, with figures a tracked Asus Xtion frame has, and
// an output like the others (named .csv, never overwritten without --force).
TEST(ReconstructReport, FrameLogHasARowPerFrame) {
  const std::string dir = test::tempDir("report_frame_log");
  const std::vector<std::string> base = {"reconstruct", test::dataPath("tum_fr3_teddy_head60"), "-o",
                                         dir + "/scene.vdb", "-q", "--max-frames", "12", "--voxel-size-m", "0.02"};
  auto with = [&](const std::vector<std::string>& extra) { return runVdbfuse(test::withArgs(base, extra)); };
  const test::CliRun run = with({"--frame-log", dir + "/frames.csv"});
  ASSERT_EQ(run.status, 0) << run.output;
  std::istringstream log(test::fileContent(dir + "/frames.csv"));
  std::string line;
  ASSERT_TRUE(std::getline(log, line));
  EXPECT_EQ(line.rfind("frame,timestamp,status,fused,matched,on_model,rmse_mm,", 0), 0u) << line;
  int rows = 0;
  while (std::getline(log, line)) {
    std::vector<std::string> f;
    std::istringstream row(line);
    for (std::string field; std::getline(row, field, ',');) f.push_back(field);
    ASSERT_GE(f.size(), 15u) << line;
    EXPECT_EQ(std::stoi(f[0]), rows) << line;
    EXPECT_EQ(f[2], rows == 0 ? "map start" : "tracked") << line;
    EXPECT_EQ(f[3], "1") << line;
    EXPECT_GT(std::stoi(f[14]), 0) << line;  // bricks fused
    if (rows == 0) {
      EXPECT_EQ(f[4], "") << line;  // placed, not matched
    } else {
      EXPECT_GT(std::stod(f[4]), 0.5) << line;
      EXPECT_GT(std::stod(f[6]), 0.5) << line;  // rmse, mm: the sensor's noise, not zero
      EXPECT_LT(std::stod(f[6]), 15.0) << line;
      EXPECT_EQ(f[7], "0") << line;             // the teddy's views leave no direction free
      EXPECT_LT(std::stod(f[11]), 5.0) << line;  // a hand-held step, cm
    }
    ++rows;
  }
  EXPECT_EQ(rows, 12);

  const test::CliRun misnamed = with({"-f", "--frame-log", dir + "/frames.txt"});
  EXPECT_EQ(misnamed.status, 1) << misnamed.output;
  EXPECT_NE(misnamed.output.find("--frame-log"), std::string::npos) << misnamed.output;
  // The scene and its trajectory gone, the log alone stands in the way.
  std::filesystem::remove(dir + "/scene.vdb");
  std::filesystem::remove(dir + "/scene.txt");
  test::writeText(dir + "/old.csv", "old\n");
  const test::CliRun kept = with({"--frame-log", dir + "/old.csv"});
  EXPECT_EQ(kept.status, 1) << kept.output;
  EXPECT_NE(kept.output.find(dir + "/old.csv"), std::string::npos) << kept.output;
  EXPECT_EQ(test::fileContent(dir + "/old.csv"), "old\n");
  EXPECT_FALSE(std::filesystem::exists(dir + "/scene.vdb"));
}

}  // namespace
}  // namespace vf
