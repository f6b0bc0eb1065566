// reconstruct --report-json: the figures a workflow's summary reads (workflow/scripts/summary.py)
// must be the ones the run prints for a person, and the report is an output like the others.
#include <gtest/gtest.h>

#include <filesystem>
#include <regex>

#include "reliability/cli_harness.h"
#include "test_data.h"

namespace vf {
namespace {

using test::runVdbfuse;

// The number after "key": in the report (the report is flat but for lost_by_reason).
double figure(const std::string& json, const std::string& key) {
  const size_t at = json.find("\"" + key + "\": ");
  if (at == std::string::npos) {
    ADD_FAILURE() << "no " << key << " in " << json;
    return -1;
  }
  return std::stod(json.substr(at + key.size() + 4));
}

int printed(const std::string& output, const std::string& pattern) {
  std::smatch m;
  if (!std::regex_search(output, m, std::regex(pattern))) {
    ADD_FAILURE() << "no '" << pattern << "' in:\n" << output;
    return -1;
  }
  return std::stoi(m[1]);
}

TEST(ReportJson, FiguresAreThePrintedOnes) {
  VF_REQUIRE_DATA(dataset, "tum_fr3_teddy_head60");
  const std::string dir = test::tempDir("report_json_figures");
  const test::CliRun run = runVdbfuse({"reconstruct", dataset, "-o", dir + "/s.vdb", "--report-json", dir + "/r.json",
                                       "--max-frames", "8", "--voxel-size-m", "0.02", "--device", "cpu", "-q"});
  ASSERT_EQ(run.status, 0) << run.output;
  const std::string json = test::fileContent(dir + "/r.json");
  EXPECT_EQ(json.front(), '{');
  EXPECT_EQ(figure(json, "frames"), printed(run.output, R"(tracked \d+ of (\d+) frames)"));
  EXPECT_EQ(figure(json, "tracked"), printed(run.output, R"(tracked (\d+) of)"));
  EXPECT_EQ(figure(json, "fused"), printed(run.output, R"(frames, fused (\d+))"));
  EXPECT_EQ(figure(json, "bricks"), printed(run.output, R"(volume: (\d+) bricks)"));
  EXPECT_EQ(figure(json, "active_voxels"), printed(run.output, R"(\((\d+) active voxels\))"));
  EXPECT_EQ(figure(json, "lost"), 0);
  // The teddy's views measure every direction: no stretch left to the motion prior, none printed.
  EXPECT_EQ(figure(json, "prior_held_frames"), 0);
  EXPECT_EQ(run.output.find("motion prior:"), std::string::npos) << run.output;
  // Eight frames come back to nothing older than the tracking model's window (300 frames): one
  // pass, no brick restarted.
  EXPECT_EQ(figure(json, "passes"), 1);
  EXPECT_EQ(figure(json, "bricks_restarted"), 0);
  EXPECT_GT(figure(json, "seconds"), 0);
  EXPECT_GT(figure(json, "peak_mib"), 10);
  EXPECT_NE(json.find("\"device\": \"cpu\""), std::string::npos) << json;
}

TEST(ReportJson, IsAnOutputLikeTheOthers) {
  VF_REQUIRE_DATA(dataset, "tum_fr3_teddy_head60");
  const std::string dir = test::tempDir("report_json_rules");
  const std::vector<std::string> base = {"reconstruct", dataset, "-o", dir + "/s.vdb", "--max-frames", "2",
                                         "--voxel-size-m", "0.02", "--device", "cpu", "-q"};
  auto with = [&](const std::vector<std::string>& extra) { return runVdbfuse(test::withArgs(base, extra)); };
  const test::CliRun misnamed = with({"--report-json", dir + "/r.txt"});
  EXPECT_EQ(misnamed.status, 1) << misnamed.output;
  EXPECT_NE(misnamed.output.find("--report-json"), std::string::npos) << misnamed.output;
  EXPECT_FALSE(std::filesystem::exists(dir + "/s.vdb"));

  test::writeText(dir + "/r.json", "old\n");
  const test::CliRun kept = with({"--report-json", dir + "/r.json"});
  EXPECT_EQ(kept.status, 1) << kept.output;
  EXPECT_NE(kept.output.find(dir + "/r.json"), std::string::npos) << kept.output;
  EXPECT_EQ(test::fileContent(dir + "/r.json"), "old\n");
}

}  // namespace
}  // namespace vf
