// Two runs given the same output (issue 35, cause 15): before, both exited 0 and one result
// silently replaced the other, and the second run's stale-temporary sweep once deleted the first
// run's live temporary. Now the second fails at once, naming the output and the first run's PID,
// and touches nothing of the first; a run killed with -9 leaves no lock that blocks the next.
#include <gtest/gtest.h>

#include <filesystem>

#include "reliability/cli_harness.h"
#include "test_data.h"

namespace vf {
namespace {

namespace fs = std::filesystem;

// Waits until `run` has a temporary under `dir` (it is writing); false if it ended first.
bool awaitTemporary(const test::BackgroundRun& run, const std::string& dir) {
  const auto deadline = std::chrono::steady_clock::now() + std::chrono::seconds(120);
  while (std::chrono::steady_clock::now() < deadline && !run.ended()) {
    if (!test::temporariesUnder(dir).empty()) return true;
    std::this_thread::sleep_for(std::chrono::milliseconds(1));
  }
  return false;
}

size_t pngsIn(const std::string& folder) {
  size_t n = 0;
  for (const auto& e : fs::directory_iterator(folder)) n += e.path().extension() == ".png";
  return n;
}

TEST(OutputLockTest, ASecondRunOnTheSameOutputFailsAtOnceAndTheFirstFinishes) {
  VF_REQUIRE_DATA(capture, "record3d_dance_head200.r3d");
  const std::string dir = test::tempDir("output_lock_second_run");
  const std::string target = dir + "/tum";
  // The whole capture (200 frames, seconds): long enough to be caught mid-write.
  test::BackgroundRun first({"convert", capture, target}, dir + "/../output_lock_first.log");
  ASSERT_TRUE(awaitTemporary(first, dir)) << first.output();
  // The first run's own temporary folder (those inside it come and go as it writes).
  std::vector<std::string> first_temporaries;
  for (const std::string& path : test::temporariesUnder(dir))
    if (fs::path(path).parent_path() == fs::path(dir)) first_temporaries.push_back(path);
  ASSERT_FALSE(first_temporaries.empty());
  const test::CliRun second = test::runVdbfuse({"convert", capture, target, "--force", "--max-frames", "2"});
  const bool first_still_running = !first.ended();
  EXPECT_EQ(second.status, 1) << second.output;
  EXPECT_NE(second.output.find(target + " is being written by another vdbfuse run (PID " + std::to_string(first.pid) +
                               ")"),
            std::string::npos)
      << second.output;
  EXPECT_LT(second.seconds, 10) << "the second run must fail at once, not wait";
  ASSERT_TRUE(first_still_running) << "the first run ended before the second was refused: the test proves nothing";
  // The second run's sweep left the first run's temporary alone.
  for (const std::string& path : first_temporaries) EXPECT_TRUE(fs::exists(path)) << path;
  EXPECT_EQ(first.wait(), 0) << first.output();
  EXPECT_EQ(pngsIn(target + "/depth"), 200u) << "the first run's result, not the second's 2 frames";
  EXPECT_EQ(test::temporariesUnder(dir), std::vector<std::string>{});
  EXPECT_FALSE(fs::exists(dir + "/.tum.lock")) << "a finished run removes its lock file";
}

TEST(OutputLockTest, ARunKilledWithSigkillBlocksNoLaterRun) {
  VF_REQUIRE_DATA(capture, "record3d_dance_head200.r3d");
  const std::string dir = test::tempDir("output_lock_killed");
  const std::string target = dir + "/tum";
  test::BackgroundRun first({"convert", capture, target}, dir + "/../output_lock_killed.log");
  ASSERT_TRUE(awaitTemporary(first, dir)) << first.output();
  kill(first.pid, SIGKILL);
  EXPECT_EQ(first.wait(), 128 + SIGKILL);
  EXPECT_TRUE(fs::exists(dir + "/.tum.lock")) << "kill -9 leaves the lock file (but not the lock)";
  const test::CliRun next = test::runVdbfuse({"convert", capture, target, "--max-frames", "2"});
  EXPECT_EQ(next.status, 0) << next.output;
  EXPECT_EQ(pngsIn(target + "/depth"), 2u);
  EXPECT_EQ(test::temporariesUnder(dir), std::vector<std::string>{}) << "the killed run's leftovers are swept";
  EXPECT_FALSE(fs::exists(dir + "/.tum.lock"));
}

}  // namespace
}  // namespace vf
