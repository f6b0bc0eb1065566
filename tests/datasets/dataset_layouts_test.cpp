// The 7-Scenes/3DMatch, Replica, ScanNet and Redwood readers on synthetic folders of their
// layouts (dataset_fixtures.h), the shared 7-Scenes and Replica captures, and their text files.
#include <gtest/gtest.h>

#include <cmath>
#include <filesystem>

#include "core/error.h"
#include "dataset_fixtures.h"
#include "io/dataset_layouts.h"
#include "io/dataset_text.h"
#include "io/frame_list_source.h"
#include "test_data.h"

namespace vf {
namespace {

using test::errorOf;
namespace fs = std::filesystem;

double poseDifference(const Pose& a, const Pose& b) { return (a.matrix() - b.matrix()).cwiseAbs().maxCoeff(); }

// Depth at a pixel where the fixture's wall is seen.
void expectWallDepth(const RgbdFrame& frame, const Pose& pose, double tolerance_m) {
  const DepthImage expected = test::wallDepth(pose);
  for (const auto& [x, y] : std::vector<std::pair<int, int>>{{10, 10}, {40, 30}, {63, 47}})
    EXPECT_NEAR(frame.depth(x, y), expected(x, y), tolerance_m) << "pixel " << x << "," << y;
}

TEST(SevenScenes, ReadsPosesIntrinsicsMillimetreDepthAndTimestamps) {
  const std::string dir = test::tempDir("seven_scenes");
  const std::vector<Pose> poses = test::fixturePoses(5);
  test::writeSevenScenes(dir, poses);
  ASSERT_TRUE(looksLikeSevenScenes(dir));
  EXPECT_FALSE(looksLikeReplica(dir) || looksLikeScanNet(dir) || looksLikeRedwood(dir));
  const FrameListSource source(readSevenScenes(dir));
  ASSERT_EQ(source.size(), 5);
  const Intrinsics k = source.depthIntrinsics();
  EXPECT_FLOAT_EQ(k.fx, test::kFixtureFx);
  EXPECT_FLOAT_EQ(k.cy, test::kFixtureCy);
  EXPECT_EQ(k.width, 64);
  EXPECT_FALSE(source.colorRegisteredToDepth());  // another sensor: tracking is geometric (seven_scenes.cpp)
  for (int i = 0; i < 5; ++i) {
    const RgbdFrame f = source.load(i);
    EXPECT_DOUBLE_EQ(f.timestamp, i / 30.0);
    ASSERT_TRUE(f.T_world_cam_given);
    EXPECT_LT(poseDifference(*f.T_world_cam_given, poses[size_t(i)]), 1e-12);
    expectWallDepth(f, poses[size_t(i)], 0.0006);  // mm steps
    EXPECT_EQ(f.depth(0, 0), 0.f) << "65535 is no reading";
    EXPECT_EQ(f.depth(3, 3), 0.f);
    EXPECT_EQ(f.color.width(), 64);
    EXPECT_EQ(f.name, "frame-" + test::sixDigits(i));
  }
  const Trajectory gt = source.groundTruth();
  ASSERT_EQ(gt.size(), 5u);
  EXPECT_DOUBLE_EQ(gt[3].timestamp, 0.1);
}

TEST(SevenScenes, WithoutIntrinsicsFileUsesTheDocumentedCamera) {
  const std::string dir = test::tempDir("seven_scenes_no_k");
  test::writeSevenScenes(dir, test::fixturePoses(2), 1000, false);
  const FrameList list = readSevenScenes(dir);
  EXPECT_EQ(list.fx, 585.f);
  EXPECT_EQ(list.cx, 320.f);
  EXPECT_NE(list.intrinsics_source.find("585"), std::string::npos);
}

TEST(SevenScenes, ThreeDMatchIntrinsicsOneFolderUpAreUsed) {
  const std::string scene = test::tempDir("threedmatch");
  test::writeSevenScenes(scene + "/seq-01", test::fixturePoses(2), 1000, false);
  test::writeText(scene + "/camera-intrinsics.txt", "570.3 0 320\n0 570.3 240\n0 0 1\n");
  const FrameList list = readSevenScenes(scene + "/seq-01");
  EXPECT_FLOAT_EQ(list.fx, 570.3f);
  EXPECT_NE(list.intrinsics_source.find("camera-intrinsics.txt"), std::string::npos);
}

TEST(SevenScenes, DepthScaleOverrideIsApplied) {
  const std::string dir = test::tempDir("seven_scenes_scale");
  const std::vector<Pose> poses = test::fixturePoses(2);
  test::writeSevenScenes(dir, poses, 5000);  // stored in TUM's units
  LayoutOptions options;
  options.depth_units_per_metre = 5000.f;
  const FrameListSource source(readSevenScenes(dir, options));
  expectWallDepth(source.load(1), poses[1], 0.00011);
  EXPECT_NE(source.description().find("5000 units/m"), std::string::npos) << source.description();
  // Without the override the same files read 5x too far.
  const FrameListSource wrong(readSevenScenes(dir));
  EXPECT_NEAR(wrong.load(1).depth(40, 30), 5 * source.load(1).depth(40, 30), 0.01);
}

TEST(SevenScenes, MalformedPoseNamesTheFile) {
  const std::string dir = test::tempDir("seven_scenes_bad");
  test::writeSevenScenes(dir, test::fixturePoses(2));
  test::writeText(dir + "/frame-000001.pose.txt", "1 0 0\n0 1 0 0\n");
  EXPECT_NE(errorOf([&] { readSevenScenes(dir); }).find("frame-000001.pose.txt"), std::string::npos);
  test::writeText(dir + "/frame-000001.pose.txt", "2 0 0 0\n0 1 0 0\n0 0 1 0\n0 0 0 1\n");
  EXPECT_NE(errorOf([&] { readSevenScenes(dir); }).find("not a rotation"), std::string::npos);
}

TEST(Replica, ReadsTrajCamParamsOneFolderUpAndItsScale) {
  const std::string dir = test::tempDir("replica");
  const std::vector<Pose> poses = test::fixturePoses(4);
  const std::string scene = test::writeReplica(dir, poses);
  ASSERT_TRUE(looksLikeReplica(scene));
  EXPECT_FALSE(looksLikeSevenScenes(scene));
  const FrameListSource source(readReplica(scene));
  ASSERT_EQ(source.size(), 4);
  EXPECT_EQ(source.list().depth_units_per_metre, 6553.5f);
  EXPECT_NE(source.list().intrinsics_source.find("cam_params.json"), std::string::npos);
  EXPECT_TRUE(source.colorRegisteredToDepth());
  for (int i = 0; i < 4; ++i) {
    const RgbdFrame f = source.load(i);
    ASSERT_TRUE(f.T_world_cam_given);
    EXPECT_LT(poseDifference(*f.T_world_cam_given, poses[size_t(i)]), 1e-12);
    expectWallDepth(f, poses[size_t(i)], 0.5 / 6553.5 + 1e-6);
  }
}

TEST(Replica, TrajectoryShorterThanTheFramesIsAnError) {
  const std::string dir = test::tempDir("replica_short");
  const std::string scene = test::writeReplica(dir, test::fixturePoses(3));
  std::string traj = readTextFile(scene + "/traj.txt");
  traj = traj.substr(0, traj.find('\n') + 1);
  test::writeText(scene + "/traj.txt", traj);
  const std::string e = errorOf([&] { readReplica(scene); });
  EXPECT_NE(e.find("traj.txt holds 1 poses"), std::string::npos) << e;
}

TEST(Replica, CamParamsSizeMustMatchTheImages) {
  const std::string dir = test::tempDir("replica_size");
  const std::string scene = test::writeReplica(dir, test::fixturePoses(2));
  test::writeText(dir + "/cam_params.json", "{\"camera\": {\"w\": 1200, \"h\": 680, \"fx\": 600.0, \"fy\": 600.0, "
                                            "\"cx\": 599.5, \"cy\": 339.5, \"scale\": 6553.5}}");
  const std::string e = errorOf([&] { FrameListSource s(readReplica(scene)); });
  EXPECT_NE(e.find("1200x680"), std::string::npos) << e;
}

TEST(ScanNet, ColourIsResizedToDepthAndLostPosesAreLeftOut) {
  const std::string dir = test::tempDir("scannet");
  const std::vector<Pose> poses = test::fixturePoses(4);
  test::writeScanNet(dir, poses, 2);
  ASSERT_TRUE(looksLikeScanNet(dir));
  EXPECT_FALSE(looksLikeRedwood(dir)) << "ScanNet's color/ + depth/ must not read as Redwood";
  const FrameListSource source(readScanNet(dir));
  ASSERT_EQ(source.size(), 4);
  EXPECT_FALSE(source.colorRegisteredToDepth());
  const RgbdFrame f = source.load(0);
  ASSERT_EQ(f.color.width(), 64);
  ASSERT_EQ(f.color.height(), 48);
  EXPECT_GT(f.color(5, 20).r, 240);  // left half red
  EXPECT_LT(f.color(5, 20).b, 15);
  EXPECT_GT(f.color(58, 20).b, 240);  // right half blue
  expectWallDepth(f, poses[0], 0.0006);
  EXPECT_FALSE(source.load(2).T_world_cam_given) << "-inf pose = tracking lost";
  ASSERT_TRUE(source.load(3).T_world_cam_given);
  EXPECT_LT(poseDifference(*source.load(3).T_world_cam_given, poses[3]), 1e-12);
  EXPECT_EQ(source.groundTruth().size(), 3u);
}

TEST(ScanNet, FramesAreInNumericOrder) {
  const std::string dir = test::tempDir("scannet_order");
  test::writeScanNet(dir, test::fixturePoses(12));
  const FrameListSource source(readScanNet(dir));
  EXPECT_EQ(source.load(2).name, "2");
  EXPECT_EQ(source.load(10).name, "10");
  EXPECT_DOUBLE_EQ(source.load(10).timestamp, 10 / 30.0);
}

TEST(Redwood, ReadsLogTrajectoryAndOpen3dIntrinsics) {
  const std::string dir = test::tempDir("redwood");
  const std::vector<Pose> poses = test::fixturePoses(3);
  test::writeRedwood(dir, poses);
  ASSERT_TRUE(looksLikeRedwood(dir));
  EXPECT_FALSE(looksLikeScanNet(dir));
  const FrameListSource source(readRedwood(dir));
  ASSERT_EQ(source.size(), 3);
  EXPECT_FLOAT_EQ(source.depthIntrinsics().cx, 31.5f);
  for (int i = 0; i < 3; ++i) {
    const RgbdFrame f = source.load(i);
    ASSERT_TRUE(f.T_world_cam_given);
    EXPECT_LT(poseDifference(*f.T_world_cam_given, poses[size_t(i)]), 1e-12);
    expectWallDepth(f, poses[size_t(i)], 0.0006);
  }
}

TEST(Redwood, LogEntryBeyondTheFramesIsAnError) {
  const std::string dir = test::tempDir("redwood_bad");
  test::writeRedwood(dir, test::fixturePoses(2));
  test::writeText(dir + "/trajectory.log", "5 5 6\n1 0 0 0\n0 1 0 0\n0 0 1 0\n0 0 0 1\n");
  const std::string e = errorOf([&] { readRedwood(dir); });
  EXPECT_NE(e.find("trajectory.log"), std::string::npos) << e;
  EXPECT_NE(e.find("frame 5"), std::string::npos) << e;
}

TEST(DatasetText, ParsersNameFileAndLine) {
  EXPECT_EQ(errorOf([] { parseReplicaTrajectory("1 0 0 0 0 1 0 0 0 0 1 0 0 0 0 1\n1 2 3\n", "t.txt"); })
                .find("t.txt:2"),
            0u);
  EXPECT_EQ(errorOf([] { parseLogTrajectory("0 0 1\n1 0 0 0\n0 1 0 0\n", "a.log"); }).find("a.log:1"), 0u);
  EXPECT_NE(errorOf([] { parseIntrinsicMatrix("1 2 3", "k.txt"); }).find("3x3 or 4x4"), std::string::npos);
  EXPECT_NE(errorOf([] { parseIntrinsicMatrix("500 0 320\n0 500 240\n0 0 2", "k.txt"); }).find("pinhole"),
            std::string::npos);
  EXPECT_NE(errorOf([] { parseNumbers("1 2 x3", "n.txt"); }).find("'x3'"), std::string::npos);
  const PinholeMatrix k = parseIntrinsicMatrix("577.6 0 318.9 0\n0 577.6 238.4 0\n0 0 1 0\n0 0 0 1\n", "k");
  EXPECT_FLOAT_EQ(k.fx, 577.6f);
  EXPECT_FLOAT_EQ(k.cy, 238.4f);
}

TEST(DatasetText, SlightlyNonOrthonormalPosesAreCleanedUp) {
  // redkitchen frame-000000.pose.txt: KinectFusion's float rotation, written with 8 digits.
  const double m[16] = {0.90931290, 0.27262229, -0.31422433, -0.34045634, -0.27248618, 0.96104980, 0.045279626,
                        0.016469818, 0.31433925, 0.044449646, 0.94820935, 0.29656917, 0, 0, 0, 1};
  const std::optional<Pose> p = poseFromRowMajor(m, "pose");
  ASSERT_TRUE(p);
  EXPECT_LT((p->linear().transpose() * p->linear() - Eigen::Matrix3d::Identity()).norm(), 1e-12);
  EXPECT_NEAR(p->linear()(0, 0), 0.9093129, 1e-4);  // its rows are 1e-4 off unit length
  EXPECT_DOUBLE_EQ(p->translation().z(), 0.29656917);
}

TEST(FrameListSource, AreaResizeAveragesCoveredPixels) {
  ColorImage c(4, 2);
  for (int x = 0; x < 4; ++x)
    for (int y = 0; y < 2; ++y) c(x, y) = {uint8_t(x * 60), uint8_t(y * 100), 0, 255};
  const ColorImage half = resizeColorArea(c, 2, 1);
  EXPECT_EQ(half(0, 0).r, 30);  // mean of 0 and 60
  EXPECT_EQ(half(1, 0).r, 150);
  EXPECT_EQ(half(0, 0).g, 50);
  const ColorImage third = resizeColorArea(c, 3, 2);  // fractional cover: 4/3 input pixels each
  EXPECT_EQ(third(0, 0).r, 15);  // (0 * 1 + 60 * 1/3) / (4/3)
}

TEST(SharedData, SevenScenesRedkitchenOpensInMillimetresWithItsPoses) {
  VF_REQUIRE_DATA(dir, "7scenes_redkitchen_head100");
  const FrameListSource source(readSevenScenes(dir));
  ASSERT_EQ(source.size(), 100);
  EXPECT_FLOAT_EQ(source.depthIntrinsics().fx, 585.f);
  const RgbdFrame f = source.load(0);
  std::vector<float> valid;
  for (int i = 0; i < f.depth.width() * f.depth.height(); ++i)
    if (f.depth.data()[i] > 0) valid.push_back(f.depth.data()[i]);
  std::nth_element(valid.begin(), valid.begin() + valid.size() / 2, valid.end());
  EXPECT_GT(valid[valid.size() / 2], 0.5f);
  EXPECT_LT(valid[valid.size() / 2], 4.0f);
  EXPECT_LE(*std::max_element(valid.begin(), valid.end()), 10.f) << "65535 must not read as 65.5 m";
  EXPECT_NEAR(f.T_world_cam_given->translation().z(), 0.29656917, 1e-7);
  EXPECT_EQ(source.groundTruth().size(), 100u);
}

TEST(SharedData, ReplicaOffice0OpensWithCamParamsOneFolderUp) {
  VF_REQUIRE_DATA(dir, "replica_office0/office0");
  const FrameListSource source(readReplica(dir));
  ASSERT_EQ(source.size(), 4);
  EXPECT_EQ(source.depthIntrinsics().width, 1200);
  EXPECT_FLOAT_EQ(source.depthIntrinsics().cx, 599.5f);
  EXPECT_EQ(source.list().depth_units_per_metre, 6553.5f);
  EXPECT_TRUE(source.load(3).T_world_cam_given);
}

}  // namespace
}  // namespace vf
