// A full disk under every writer: each command runs with RLIMIT_FSIZE below its output's size
// (SIGXFSZ ignored, so writes fail with EFBIG as on a full disk) and must fail with exit 1 and a
// message naming the output, leave no temporary, keep the old output and its inputs as they were,
// and report nothing as written that is not whole.
#include <gtest/gtest.h>

#include <filesystem>

#include "reliability/cli_harness.h"
#include "reliability/scene_fixture.h"
#include "test_data.h"

namespace vf {
namespace {

namespace fs = std::filesystem;
using test::runVdbfuse;

constexpr uint64_t kSmallDisk = 4096;  // bytes: less than any output below
const std::string kOld = "old output, must survive\n";

class FullDiskTest : public ::testing::Test {
 protected:
  void SetUp() override {
    dir_ = test::tempDir(std::string("full_disk_") + ::testing::UnitTest::GetInstance()->current_test_info()->name());
    scene_ = test::writeSceneFixture(dir_);
  }

  // Runs `args` on the small disk; `target` is the output that cannot fit. When it is a file it
  // holds kOld before (the run has --force), when a folder it holds old/keep.txt.
  void expectCleanFailure(std::vector<std::string> args, const std::string& target, bool folder = false) {
    SCOPED_TRACE(target);
    if (folder) {
      fs::create_directories(target);
      test::writeText(target + "/keep.txt", kOld);
    } else {
      test::writeText(target, kOld);
    }
    const auto before = test::snapshot(dir_);
    const test::CliRun run = runVdbfuse(args, kSmallDisk);
    EXPECT_EQ(run.status, 1) << run.output;
    EXPECT_NE(run.output.find("error"), std::string::npos) << run.output;
    EXPECT_NE(run.output.find(target), std::string::npos)
        << "the message does not name the output:\n" << run.output;
    EXPECT_EQ(run.output.find("wrote " + target), std::string::npos) << run.output;
    EXPECT_EQ(run.output.find("internal error"), std::string::npos) << run.output;
    EXPECT_EQ(test::temporariesUnder(dir_), std::vector<std::string>{});
    EXPECT_EQ(test::changedFiles(before, test::snapshot(dir_)), std::vector<std::string>{}) << "a failed run changed a file";
    // The same run on a disk with room succeeds: the limit, not the command, made it fail.
    const test::CliRun roomy = runVdbfuse(args);
    EXPECT_EQ(roomy.status, 0) << roomy.output;
  }

  std::string dir_, scene_;
};

TEST_F(FullDiskTest, MeshInEachFormat) {
  for (const std::string ext : {".ply", ".obj", ".glb"})
    expectCleanFailure({"mesh", scene_, "-o", dir_ + "/mesh" + ext, "--force"}, dir_ + "/mesh" + ext);
}

TEST_F(FullDiskTest, MeshPerClassWritesAllOrNothing) {
  // Two class meshes; neither may be left when the second cannot be written.
  test::writeText(dir_ + "/m_a_b.ply", kOld);
  expectCleanFailure({"mesh", scene_, "-o", dir_ + "/m.ply", "--per-class", "--force"}, dir_ + "/m_a_b.ply");
}

TEST_F(FullDiskTest, Edit) {
  expectCleanFailure({"edit", scene_, "-o", dir_ + "/clean.vdb", "--force"}, dir_ + "/clean.vdb");
}

TEST_F(FullDiskTest, ExportPoints) {
  expectCleanFailure({"export", scene_, "--points", "-o", dir_ + "/points.ply", "--force"}, dir_ + "/points.ply");
}

TEST_F(FullDiskTest, ExportBlenderFolder) {
  expectCleanFailure({"export", scene_, "--blender", "-o", dir_ + "/blender", "--force"}, dir_ + "/blender", true);
  EXPECT_TRUE(fs::exists(dir_ + "/blender/volume.vdb"));
}

TEST_F(FullDiskTest, ReconstructScene) {
  VF_REQUIRE_DATA(dataset, "tum_fr3_teddy_head60");
  expectCleanFailure({"reconstruct", dataset, "-o", dir_ + "/fused.vdb", "--max-frames", "3", "--voxel-size-m", "0.02",
                      "--device", "cpu", "-q", "--force"},
                     dir_ + "/fused.vdb");
}

TEST_F(FullDiskTest, ReconstructCheckpoint) {
  VF_REQUIRE_DATA(dataset, "tum_fr3_teddy_head60");
  // The checkpoint (bricks at full precision) is larger than the scene: a disk that holds the
  // scene and the trajectory but not the checkpoint.
  const std::vector<std::string> args = {"reconstruct", dataset, "-o", dir_ + "/fused.vdb", "--max-frames", "3",
                                         "--voxel-size-m", "0.02", "--device", "cpu", "-q", "--checkpoint-every", "1"};
  ASSERT_EQ(runVdbfuse(args).status, 0);
  const uint64_t scene_bytes = fs::file_size(dir_ + "/fused.vdb");
  fs::remove(dir_ + "/fused.vdb");
  fs::remove(dir_ + "/fused.txt");
  const test::CliRun run = runVdbfuse(args, scene_bytes + 1024);
  EXPECT_EQ(run.status, 1) << run.output;
  EXPECT_NE(run.output.find("fused.vdb.checkpoint"), std::string::npos) << run.output;
  EXPECT_EQ(run.output.find("internal error"), std::string::npos) << run.output;
  EXPECT_EQ(test::temporariesUnder(dir_), std::vector<std::string>{});
  EXPECT_FALSE(fs::exists(dir_ + "/fused.vdb.checkpoint"));
}

TEST_F(FullDiskTest, ConvertFolder) {
  VF_REQUIRE_DATA(capture, "record3d_dance_head200.r3d");
  expectCleanFailure({"convert", capture, dir_ + "/tum", "--max-frames", "2", "--force"}, dir_ + "/tum", true);
}

TEST_F(FullDiskTest, ViewScreenshot) {
  const std::string viewer = fs::path(test::vdbfuseExe()).parent_path().string() + "/vdbfuse-view";
  if (!fs::exists(viewer)) GTEST_SKIP() << "built without the viewer (-DVDBFUSE_WITH_VIEWER=OFF)";
  if (!fs::exists("/usr/bin/xvfb-run")) GTEST_SKIP() << "no xvfb-run: the viewer renders through X";
  // The limit on the viewer alone (a shell inside xvfb-run), not on the X server.
  const std::string shot = dir_ + "/shot.png";
  test::writeText(shot, kOld);
  const auto before = test::snapshot(dir_);
  int status = 0;
  const std::string output = test::runCommand(
      test::underXvfb("/usr/bin/xvfb-run", "trap '' XFSZ; ulimit -f " + std::to_string(kSmallDisk / 512) + "; " +
                                               viewer + " " + scene_ + " --screenshot " + shot +
                                               " --force --size 320x240"),
      status);
  EXPECT_EQ(test::xvfbExitStatus(output), 1) << output;
  EXPECT_NE(output.find(shot), std::string::npos) << output;
  EXPECT_EQ(output.find("wrote " + shot), std::string::npos) << output;
  EXPECT_EQ(test::temporariesUnder(dir_), std::vector<std::string>{});
  EXPECT_EQ(test::changedFiles(before, test::snapshot(dir_)), std::vector<std::string>{});
  const std::string roomy = test::runCommand(
      test::underXvfb("/usr/bin/xvfb-run", viewer + " " + scene_ + " --screenshot " + shot + " --force --size 320x240"),
      status);
  EXPECT_EQ(test::xvfbExitStatus(roomy), 0) << "the same screenshot with room on the disk:\n" << roomy;
}

}  // namespace
}  // namespace vf
