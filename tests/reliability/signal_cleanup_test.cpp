// Signals at any moment: every command removes its temporaries and keeps the old outputs when
// SIGINT or SIGTERM ends it, and reconstruct, once saving, answers further signals with "still
// saving" and saves whole.
#include <gtest/gtest.h>

#include <filesystem>
#include <random>

#include "fusion/checkpoint.h"
#include "io/trajectory_io.h"
#include "reliability/cli_harness.h"
#include "reliability/scene_fixture.h"
#include "test_data.h"

namespace vf {
namespace {

namespace fs = std::filesystem;

const std::string kOld = "the old output\n";

// Signals `command` at times spread over its run: each run either finishes (status 0, the new
// output in place) or dies of the signal (128 + signal) with the old output, or the whole new one
// when the signal came after the rename; none leaves a temporary.
void signalAtRandomTimes(const std::string& dir, const std::vector<std::string>& args, const std::string& target,
                         bool folder, int signal) {
  SCOPED_TRACE(args[0]);
  const auto state = [&] {
    auto files = folder ? test::snapshot(target)
                        : std::vector<std::pair<std::string, std::string>>{{target, test::fileContent(target)}};
    for (auto& [path, bytes] : files) bytes = test::withoutVdbUuid(path, bytes);
    return files;
  };
  const auto putOld = [&] {
    fs::remove_all(target);
    if (folder) {
      fs::create_directories(target);
      test::writeText(target + "/old.txt", kOld);
    } else {
      test::writeText(target, kOld);
    }
    return state();
  };
  const auto old_state = putOld();
  const test::CliRun reference = test::runVdbfuse(args);
  ASSERT_EQ(reference.status, 0) << reference.output;
  const auto new_state = state();
  std::mt19937 rng(16);
  std::uniform_real_distribution<double> when(0.0, 1.1 * reference.seconds);
  int interrupted = 0;
  for (int attempt = 0; attempt < 12; ++attempt) {
    putOld();
    test::BackgroundRun run(args, dir + "/../" + fs::path(dir).filename().string() + ".log");
    std::this_thread::sleep_for(std::chrono::duration<double>(attempt == 0 ? 0.05 : when(rng)));
    kill(run.pid, signal);
    const int status = run.wait();
    SCOPED_TRACE("attempt " + std::to_string(attempt) + ", status " + std::to_string(status) + ": " + run.output());
    ASSERT_TRUE(status == 0 || status == 128 + signal);
    EXPECT_EQ(test::temporariesUnder(dir), std::vector<std::string>{});
    const auto now = state();
    if (status == 0) {
      EXPECT_EQ(test::changedFiles(new_state, now), std::vector<std::string>{}) << "a finished run left another output";
    } else {
      ++interrupted;
      EXPECT_TRUE(now == old_state || now == new_state)
          << "an interrupted run left a changed or partial output: "
          << ::testing::PrintToString(test::changedFiles(old_state, now));
    }
  }
  EXPECT_GE(interrupted, 3) << "the signal never arrived mid-run";
}

class SignalCleanupTest : public ::testing::Test {
 protected:
  void SetUp() override {
    dir_ = test::tempDir(std::string("signals_") + ::testing::UnitTest::GetInstance()->current_test_info()->name());
    scene_ = test::writeSceneFixture(dir_, 160, 0.005f);  // large enough to take a while to mesh and write
  }
  std::string dir_, scene_;
};

TEST_F(SignalCleanupTest, MeshLeavesNoTemporary) {
  signalAtRandomTimes(dir_, {"mesh", scene_, "-o", dir_ + "/mesh.ply", "--force"}, dir_ + "/mesh.ply", false, SIGINT);
}

TEST_F(SignalCleanupTest, EditLeavesNoTemporary) {
  signalAtRandomTimes(dir_, {"edit", scene_, "-o", dir_ + "/clean.vdb", "--smooth", "1", "--force"},
                      dir_ + "/clean.vdb", false, SIGTERM);
}

TEST_F(SignalCleanupTest, BlenderExportLeavesNoTemporary) {
  signalAtRandomTimes(dir_, {"export", scene_, "--blender", "-o", dir_ + "/blender", "--force"}, dir_ + "/blender", true,
                      SIGINT);
}

TEST_F(SignalCleanupTest, ConvertLeavesNoTemporary) {
  VF_REQUIRE_DATA(capture, "record3d_dance_head200.r3d");
  signalAtRandomTimes(dir_, {"convert", capture, dir_ + "/tum", "--max-frames", "20", "--force"}, dir_ + "/tum", true,
                      SIGTERM);
}

TEST_F(SignalCleanupTest, RepeatedCtrlCDuringTheSaveWaitsForTheSave) {
  VF_REQUIRE_DATA(dataset, "tum_fr3_teddy_head60");
  const std::string scene = dir_ + "/fused.vdb", trajectory = dir_ + "/fused.txt";
  test::BackgroundRun run({"reconstruct", dataset, "-o", scene, "--max-frames", "40", "--device", "cpu", "-q",
                           "--renders", dir_ + "/renders"},
                          dir_ + "/reconstruct.log");
  // A sign of progress (the third frame's render), not a fixed sleep.
  const auto deadline = std::chrono::steady_clock::now() + std::chrono::seconds(120);
  while (!fs::exists(dir_ + "/renders/frame_00002.png") && std::chrono::steady_clock::now() < deadline)
    std::this_thread::sleep_for(std::chrono::milliseconds(5));
  ASSERT_TRUE(fs::exists(dir_ + "/renders/frame_00002.png")) << run.output();
  kill(run.pid, SIGINT);
  ASSERT_TRUE(run.waitForOutput("SIGINT: finishing this frame")) << run.output();
  // Ctrl-C again and again until it ends: through the rest of the frame and the whole save.
  int sent = 1;
  while (!run.ended()) {
    kill(run.pid, SIGINT);
    ++sent;
    std::this_thread::sleep_for(std::chrono::milliseconds(20));
  }
  EXPECT_EQ(run.wait(), 130) << run.output();
  EXPECT_GE(sent, 3);
  EXPECT_NE(run.output().find("still saving"), std::string::npos) << run.output();
  EXPECT_EQ(test::temporariesUnder(dir_), std::vector<std::string>{});
  const int done = int(readTumTrajectory(trajectory).size());
  EXPECT_GT(done, 2);
  EXPECT_LT(done, 40);
  EXPECT_EQ(readScene(scene).meta.frame_count, done);
  EXPECT_NO_THROW(readCheckpointSettings(scene + ".checkpoint"));
}

}  // namespace
}  // namespace vf
