// `vdbfuse convert` on every input `reconstruct` reads (issue 35, cause 20: the README promised
// "any readable input as a TUM folder" and convert refused all but Record3D), read back with the
// TUM reader; and reader errors through the CLI that blamed an option not given or an internal
// name (causes 19 and 24).
#include <gtest/gtest.h>

#include <filesystem>

#include "dataset_fixtures.h"
#include "io/dataset_layouts.h"
#include "io/frame_list_source.h"
#include "io/tum_dataset.h"
#include "test_data.h"

namespace vf {
namespace {

namespace fs = std::filesystem;

std::string vdbfuse(const std::string& args, int& status) {
  return test::runCommand(std::string(VDBFUSE_EXE) + " " + args, status);
}

double maxPoseDifference(const Pose& a, const Pose& b) { return (a.matrix() - b.matrix()).cwiseAbs().maxCoeff(); }

// The TUM folder holds the source's frames: depth to TUM's 0.2 mm steps, colour as decoded (PNG,
// lossless, at the depth size), the same poses and timestamps, the same camera.
void expectSameFrames(const FrameSource& source, const TumDataset& tum, int frames) {
  ASSERT_EQ(tum.size(), frames);
  const Intrinsics a = source.depthIntrinsics(), b = tum.depthIntrinsics();
  EXPECT_NEAR(b.fx, a.fx, 1e-4);
  EXPECT_NEAR(b.cy, a.cy, 1e-4);
  EXPECT_EQ(b.width, a.width);
  for (int i = 0; i < frames; ++i) {
    const RgbdFrame in = source.load(i), out = tum.load(i);
    EXPECT_NEAR(out.timestamp, in.timestamp, 1e-6) << "frame " << i;
    double worst_m = 0;
    for (int k = 0; k < in.depth.width() * in.depth.height(); ++k)
      worst_m = std::max(worst_m, double(std::abs(in.depth.data()[k] - out.depth.data()[k])));
    EXPECT_LE(worst_m, 0.5 / 5000 + 1e-6) << "frame " << i;
    ASSERT_EQ(out.color.width(), in.depth.width()) << "frame " << i;
    if (in.color.width() == in.depth.width()) {
      const Rgb8 p = in.color(17, 13), q = out.color(17, 13);
      EXPECT_EQ(int(p.r) + 1000 * int(p.g) + 1000000 * int(p.b), int(q.r) + 1000 * int(q.g) + 1000000 * int(q.b))
          << "frame " << i;
    }
    ASSERT_EQ(bool(in.T_world_cam_given), bool(out.T_world_cam_given)) << "frame " << i;
    if (in.T_world_cam_given) {
      EXPECT_LT(maxPoseDifference(*in.T_world_cam_given, *out.T_world_cam_given), 1e-6) << "frame " << i;
    }
  }
}

TEST(ConvertCli, SevenScenesRoundTripsThroughATumFolder) {
  VF_REQUIRE_DATA(kitchen, "7scenes_redkitchen_head100");
  const std::string out = test::tempDir("convert_7scenes") + "/tum";
  int status = 0;
  const std::string log = vdbfuse("convert " + kitchen + " " + out + " --max-frames 6", status);
  ASSERT_EQ(status, 0) << log;
  EXPECT_NE(log.find("wrote 6 frames and 6 poses"), std::string::npos) << log;
  const FrameListSource source(readSevenScenes(kitchen));
  expectSameFrames(source, TumDataset(out), 6);
  // It reconstructs like any TUM folder, with its poses.
  const std::string again = vdbfuse("reconstruct " + out + " --poses given -q -f --voxel-size-m 0.04 -o " + out +
                                        "_scene.vdb", status);
  EXPECT_EQ(status, 0) << again;
}

TEST(ConvertCli, EveryLayoutConverts) {
  const std::vector<Pose> poses = test::fixturePoses(3);
  const std::string root = test::tempDir("convert_layouts");
  const std::string seven = root + "/seven", scannet = root + "/scannet", redwood = root + "/redwood";
  test::writeSevenScenes(seven, poses);
  test::writeScanNet(scannet, poses);
  test::writeRedwood(redwood, poses);
  const std::string replica = test::writeReplica(root + "/replica", poses);
  struct Layout {
    std::string folder;
    FrameList (*read)(const std::string&, const LayoutOptions&);
  };
  for (const Layout& layout : {Layout{seven, readSevenScenes}, Layout{scannet, readScanNet},
                               Layout{redwood, readRedwood}, Layout{replica, readReplica}}) {
    const std::string out = layout.folder + "_tum";
    int status = 0;
    const std::string log = vdbfuse("convert " + layout.folder + " " + out, status);
    ASSERT_EQ(status, 0) << log;
    EXPECT_NE(log.find("wrote 3 frames and 3 poses"), std::string::npos) << log;
    const FrameListSource source(layout.read(layout.folder, {}));
    SCOPED_TRACE(layout.folder);
    expectSameFrames(source, TumDataset(out), 3);
    if (layout.folder == scannet) {
      EXPECT_NE(log.find("not registered"), std::string::npos) << log;
    }
  }
  // A TUM folder converts too (freiburg1: undistorted on the way, so the copy has no distortion).
  VF_REQUIRE_DATA(fr1, "tum_fr1_xyz_head100");
  const std::string out = root + "/fr1_tum";
  int status = 0;
  const std::string log = vdbfuse("convert " + fr1 + " " + out + " --max-frames 3", status);
  ASSERT_EQ(status, 0) << log;
  const TumDataset converted(out);
  EXPECT_TRUE(converted.calibration().distortion.isZero());
  expectSameFrames(TumDataset(fr1), converted, 3);
}

// Cause 19: a camera-intrinsics.txt the pipeline cannot fuse was blamed on "--intrinsics", which
// was not given. Cause 24: a NaN in a pose file was "has no recorded pose (PoseSource::Given needs
// one)".
TEST(ConvertCli, ReaderErrorsNameTheFileNotAnOptionOrAnInternalName) {
  const std::string seven = test::tempDir("cli_blame_k");
  test::writeSevenScenes(seven, test::fixturePoses(3));
  test::writeText(seven + "/camera-intrinsics.txt", "60 0 3200\n0 60 23.5\n0 0 1\n");
  int status = 0;
  std::string log = vdbfuse("reconstruct " + seven + " -q -f -o " + seven + "_scene.vdb", status);
  EXPECT_NE(status, 0);
  EXPECT_NE(log.find(seven + "/camera-intrinsics.txt: cx = 3200 lies outside"), std::string::npos) << log;
  EXPECT_EQ(log.find("--intrinsics"), std::string::npos) << log;

  const std::string nan = test::tempDir("cli_blame_nan");
  test::writeSevenScenes(nan, test::fixturePoses(3));
  test::writeText(nan + "/frame-000002.pose.txt", "nan 0 0 0\n0 1 0 0\n0 0 1 0\n0 0 0 1\n");
  log = vdbfuse("reconstruct " + nan + " --poses given -q -f -o " + nan + "_scene.vdb", status);
  EXPECT_NE(status, 0);
  EXPECT_NE(log.find(nan + "/frame-000002.pose.txt: the pose holds nan at row 1, column 1"), std::string::npos) << log;
  EXPECT_EQ(log.find("PoseSource"), std::string::npos) << log;
}

}  // namespace
}  // namespace vf
