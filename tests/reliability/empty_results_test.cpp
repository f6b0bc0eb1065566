// Issue 35, causes 2, 7, 8 and 9: a run that fuses nothing says so and fails; a run whose first
// frames have no depth starts at the first frame that has some; frames whose recorded pose lies
// beyond the volume's reach are reported, not silently dropped. Through the vdbfuse binary, on
// copies of the teddy capture made in the test.
#include <gtest/gtest.h>

#include <filesystem>
#include <fstream>
#include <sstream>

#include "io/image_io.h"
#include "io/trajectory_io.h"
#include "reliability/cli_harness.h"
#include "test_data.h"

namespace vf {
namespace {

namespace fs = std::filesystem;
using test::runVdbfuse;

// A TUM folder reading `frames` of the teddy's frames from `first` on; `blank_first` of them
// with no depth, and the ground truth moved by `offset_m` (for --poses given).
std::string teddyCopy(const std::string& name, int frames, int blank_first = 0, double offset_m = 0, int first = 0) {
  const std::string src = test::dataPath("tum_fr3_teddy_head60");
  const std::string dir = test::tempDir(name);
  fs::create_directories(dir + "/depth");
  fs::create_symlink(src + "/rgb", dir + "/rgb");
  fs::copy_file(src + "/camera_intrinsics.txt", dir + "/camera_intrinsics.txt");
  fs::copy_file(src + "/rgb.txt", dir + "/rgb.txt");
  std::ifstream depth_in(src + "/depth.txt");
  std::ofstream depth_out(dir + "/depth.txt");
  int listed = 0, seen = 0;
  for (std::string line; std::getline(depth_in, line);) {
    if (line.empty() || line[0] == '#') {
      depth_out << line << "\n";
      continue;
    }
    if (seen++ < first) continue;
    if (listed == frames) break;
    const std::string file = line.substr(line.find(' ') + 1);
    if (listed < blank_first) {
      const DepthImage real = readDepthPng(src + "/" + file);
      writeDepthPng(dir + "/" + file, DepthImage(real.width(), real.height(), 0.f));
    } else {
      fs::create_symlink(src + "/" + file, dir + "/" + file);
    }
    depth_out << line << "\n";
    ++listed;
  }
  std::ifstream gt_in(src + "/groundtruth.txt");
  std::ofstream gt_out(dir + "/groundtruth.txt");
  for (std::string line; std::getline(gt_in, line);) {
    if (line.empty() || line[0] == '#') {
      gt_out << line << "\n";
      continue;
    }
    std::istringstream fields(line);
    double t, x, y, z, qx, qy, qz, qw;
    fields >> t >> x >> y >> z >> qx >> qy >> qz >> qw;
    gt_out.precision(17);
    gt_out << t << " " << x + offset_m << " " << y << " " << z << " " << qx << " " << qy << " " << qz << " " << qw << "\n";
  }
  return dir;
}

TEST(EmptyResults, BlankFirstFramesStartTheMapAtTheFirstFrameWithDepth) {
  VF_REQUIRE_DATA(src, "tum_fr3_teddy_head60");
  const std::string data = teddyCopy("empty_blank_start", 20, 2);
  const std::string out = test::tempDir("empty_blank_start_out");
  const test::CliRun run = runVdbfuse({"reconstruct", data, "-o", out + "/scene.vdb", "--loop-closure", "off"});
  ASSERT_EQ(run.status, 0) << run.output;
  EXPECT_NE(run.output.find("tracked 18 of 20 frames, fused 18"), std::string::npos) << run.output;
  EXPECT_NE(run.output.find("no valid depth"), std::string::npos) << run.output;
  EXPECT_EQ(readTumTrajectory(out + "/scene.txt").size(), 18u) << "the blank frames have no pose";
}

TEST(EmptyResults, DepthBeyondTheFusionRangeFailsNamingTheRangeAndTheOptions) {
  VF_REQUIRE_DATA(src, "tum_fr3_teddy_head60");
  const std::string out = test::tempDir("empty_far");
  // 500 units per metre: the teddy's readings become 10 times as far, 8-30 m, all beyond 4 m.
  const test::CliRun run =
      runVdbfuse({"reconstruct", src, "-o", out + "/scene.vdb", "--max-frames", "5", "--depth-scale", "500"});
  EXPECT_EQ(run.status, 1) << run.output;
  for (const char* expected : {"no frame was fused", "within 0.20-4.0 m", "--max-depth-m", "--depth-scale"})
    EXPECT_NE(run.output.find(expected), std::string::npos) << "no '" << expected << "' in:\n" << run.output;
  EXPECT_FALSE(fs::exists(out + "/scene.vdb")) << "a scene of nothing was written";
}

TEST(EmptyResults, AVanishingDepthScaleFailsInsteadOfWritingAnEmptyScene) {
  VF_REQUIRE_DATA(src, "tum_fr3_teddy_head60");
  const std::string out = test::tempDir("empty_scale");
  const test::CliRun run =
      runVdbfuse({"reconstruct", src, "-o", out + "/scene.vdb", "--max-frames", "5", "--depth-scale", "1e-30"});
  EXPECT_EQ(run.status, 1) << run.output;
  EXPECT_NE(run.output.find("no frame was fused"), std::string::npos) << run.output;
  EXPECT_FALSE(fs::exists(out + "/scene.vdb"));
}

TEST(EmptyResults, RecordedPosesBeyondTheVolumesReachAreReportedAndTheRunFails) {
  VF_REQUIRE_DATA(src, "tum_fr3_teddy_head60");
  // From frame 10 on, where the motion capture has started.
  const std::string data = teddyCopy("empty_far_poses", 6, 0, 1e6, 10);
  const std::string out = test::tempDir("empty_far_poses_out");
  const test::CliRun run = runVdbfuse({"reconstruct", data, "-o", out + "/scene.vdb", "--poses", "given"});
  EXPECT_EQ(run.status, 1) << run.output;
  for (const char* expected : {"no frame was fused", "beyond the volume's reach", "--poses icp"})
    EXPECT_NE(run.output.find(expected), std::string::npos) << "no '" << expected << "' in:\n" << run.output;
  EXPECT_FALSE(fs::exists(out + "/scene.vdb"));
}

}  // namespace
}  // namespace vf
