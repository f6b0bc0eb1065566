// Issue 35's hostile folders against the dataset layouts (7-Scenes, Replica, ScanNet, Redwood):
// frames in number order, two files of one frame number, dangling colour links, colour of another
// aspect ratio, intrinsics files that cannot be fused, non-finite poses and JSON fields of the
// wrong type. Each folder is a small synthetic one (dataset_fixtures.h), changed by the test.
#include <gtest/gtest.h>

#include <filesystem>
#include <fstream>

#include "core/error.h"
#include "dataset_fixtures.h"
#include "io/dataset_layouts.h"
#include "io/dataset_text.h"
#include "io/frame_list_source.h"
#include "io/frame_order.h"
#include "test_data.h"

namespace vf {
namespace {

using test::errorOf;
namespace fs = std::filesystem;

double poseDifference(const Pose& a, const Pose& b) { return (a.matrix() - b.matrix()).cwiseAbs().maxCoeff(); }

bool contains(const std::string& text, const std::string& part) { return text.find(part) != std::string::npos; }

// Renames every file of `folder` named <6 digits><suffix> to <number><suffix> ("000010.png" ->
// "10.png"): the names a string sort puts in the order 0, 1, 10, 11, 2.
void unpadNames(const std::string& folder) {
  for (const auto& entry : fs::directory_iterator(folder)) {
    const std::string name = entry.path().filename().string();
    const size_t dot = name.find('.');
    fs::rename(entry.path(), fs::path(folder) / (std::to_string(std::stoi(name.substr(0, dot))) + name.substr(dot)));
  }
}

TEST(FrameOrder, DigitRunsCompareAsNumbers) {
  EXPECT_LT(compareFrameNames("2.png", "10.png"), 0);
  EXPECT_GT(compareFrameNames("11.png", "2.png"), 0);
  EXPECT_EQ(compareFrameNames("1.png", "000001.png"), 0);
  EXPECT_EQ(compareFrameNames("frame-1.depth.png", "frame-000001.depth.png"), 0);
  EXPECT_EQ(compareFrameNames("7.jpg", "7.png"), 0) << "one frame, whatever its format";
  EXPECT_LT(compareFrameNames("0000001-000000000000.png", "0000002-000000033333.png"), 0);  // Redwood scans
  EXPECT_LT(compareFrameNames("99999999999999999999.png", "100000000000000000000.png"), 0) << "no overflow";
  EXPECT_LT(compareFrameNames("a2.png", "b1.png"), 0);
  std::vector<std::string> names = {"10.png", "2.png", "0.png", "1.png", "11.png"};
  sortByFrameNumber(names, "depth");
  EXPECT_EQ(names, (std::vector<std::string>{"0.png", "1.png", "2.png", "10.png", "11.png"}));
  names = {"3.png", "01.png", "1.png"};
  const std::string e = errorOf([&] { sortByFrameNumber(names, "depth"); });
  EXPECT_TRUE(contains(e, "depth: 01.png and 1.png name the same frame")) << e;
}

// Cause 4: color/ and depth/ named 0.png .. 11.png were fused as 0, 1, 10, 11, 2, ... with the
// .log poses by index: frame 2 got 10.png and pose 2.
TEST(Redwood, UnpaddedNamesAreFusedInNumberOrderWithTheirPoses) {
  const std::string dir = test::tempDir("hostile_redwood_order");
  const std::vector<Pose> poses = test::fixturePoses(12);
  test::writeRedwood(dir, poses);
  unpadNames(dir + "/color");
  unpadNames(dir + "/depth");
  ASSERT_TRUE(fs::exists(dir + "/depth/10.png"));
  const FrameListSource source(readRedwood(dir));
  ASSERT_EQ(source.size(), 12);
  for (int i : {2, 10, 11}) {
    const RgbdFrame f = source.load(i);
    EXPECT_EQ(f.name, std::to_string(i));
    ASSERT_TRUE(f.T_world_cam_given);
    EXPECT_LT(poseDifference(*f.T_world_cam_given, poses[size_t(i)]), 1e-12) << "frame " << i;
    EXPECT_NEAR(f.depth(40, 30), test::wallDepth(poses[size_t(i)])(40, 30), 0.0006) << "frame " << i;
  }
  EXPECT_EQ(source.list().frames[2].color, dir + "/color/2.jpg");
}

// Cause 12: two files of one frame number were both fused, the frame twice.
TEST(DuplicateFrames, TwoFilesOfOneNumberAreRefusedNamingBoth) {
  const std::string seven = test::tempDir("hostile_dup_7scenes");
  test::writeSevenScenes(seven, test::fixturePoses(3));
  for (const char* ext : {".depth.png", ".color.jpg", ".pose.txt"})
    fs::copy_file(seven + "/frame-000001" + ext, seven + "/frame-1" + ext);
  std::string e = errorOf([&] { readSevenScenes(seven); });
  EXPECT_TRUE(contains(e, seven + ": frame-000001.depth.png and frame-1.depth.png name the same frame")) << e;

  const std::string scannet = test::tempDir("hostile_dup_scannet");
  test::writeScanNet(scannet, test::fixturePoses(3));
  fs::copy_file(scannet + "/depth/1.png", scannet + "/depth/01.png");
  e = errorOf([&] { readScanNet(scannet); });
  EXPECT_TRUE(contains(e, "01.png and 1.png name the same frame")) << e;

  const std::string replica = test::writeReplica(test::tempDir("hostile_dup_replica"), test::fixturePoses(3));
  fs::copy_file(replica + "/results/depth000001.png", replica + "/results/depth1.png");
  e = errorOf([&] { readReplica(replica); });
  EXPECT_TRUE(contains(e, "depth000001.png and depth1.png name the same frame")) << e;

  const std::string redwood = test::tempDir("hostile_dup_redwood");
  test::writeRedwood(redwood, test::fixturePoses(3));
  fs::copy_file(redwood + "/depth/000001.png", redwood + "/depth/1.png");
  e = errorOf([&] { readRedwood(redwood); });
  EXPECT_TRUE(contains(e, "000001.png and 1.png name the same frame")) << e;
}

// Found beside cause 12: a .log with two poses for one frame kept the second without a word.
TEST(DuplicateFrames, TwoLogPosesForOneFrameAreRefusedNamingBothLines) {
  const std::string redwood = test::tempDir("hostile_dup_log");
  test::writeRedwood(redwood, test::fixturePoses(3));
  std::ofstream(redwood + "/trajectory.log", std::ios::app) << "1 1 2\n1 0 0 0\n0 1 0 0\n0 0 1 0\n0 0 0 1\n";
  const std::string e = errorOf([&] { readRedwood(redwood); });
  EXPECT_TRUE(contains(e, redwood + "/trajectory.log:16: a second pose for frame 1 (the first is at line 6)")) << e;
}

// Cause 16: ScanNet colour is resized onto the depth; colour of another shape was stretched.
TEST(ScanNet, ColourOfAnotherAspectRatioIsRefusedNotStretched) {
  const std::string dir = test::tempDir("hostile_scannet_aspect");
  test::writeScanNet(dir, test::fixturePoses(2));
  test::writeColor(dir + "/color/1.jpg", 128, 48);  // 8:3 over 4:3 depth
  const FrameListSource source(readScanNet(dir));
  EXPECT_EQ(source.load(0).color.width(), 64) << "ScanNet's own shape (2x the depth) is resized";
  const std::string e = errorOf([&] { source.load(1); });
  EXPECT_TRUE(contains(e, dir + "/color/1.jpg is 128x48")) << e;
  EXPECT_TRUE(contains(e, "is 64x48")) << e;
  EXPECT_TRUE(contains(e, "aspect ratio")) << e;
  // ScanNet's real sizes, 1296x968 over 640x480 (0.4 % apart), are no stretch.
  EXPECT_FALSE(aspectRatiosDiffer(1296, 968, 640, 480));
  EXPECT_TRUE(aspectRatiosDiffer(1296, 968, 480, 640));
}

// Cause 17: a colour image that is a dangling link was left out, the frame fused without colour.
TEST(DanglingLinks, AColourImageThatCannotBeReadIsAnErrorNamingIt) {
  const std::string seven = test::tempDir("hostile_link_7scenes");
  test::writeSevenScenes(seven, test::fixturePoses(3));
  fs::remove(seven + "/frame-000002.color.jpg");
  fs::create_symlink(seven + "/gone.jpg", seven + "/frame-000002.color.jpg");
  std::string e = errorOf([&] { FrameListSource s(readSevenScenes(seven)); });
  EXPECT_TRUE(contains(e, "colour image " + seven + "/frame-000002.color.jpg is a link to " + seven + "/gone.jpg")) << e;

  const std::string scannet = test::tempDir("hostile_link_scannet");
  test::writeScanNet(scannet, test::fixturePoses(2));
  fs::remove(scannet + "/color/1.jpg");
  fs::create_symlink("nowhere.jpg", scannet + "/color/1.jpg");
  e = errorOf([&] { FrameListSource s(readScanNet(scannet)); });
  EXPECT_TRUE(contains(e, scannet + "/color/1.jpg is a link to nowhere.jpg")) << e;

  // Redwood: every colour image a dangling link used to read as a folder without colour.
  const std::string redwood = test::tempDir("hostile_link_redwood");
  test::writeRedwood(redwood, test::fixturePoses(2));
  for (const char* n : {"000000", "000001"}) {
    fs::remove(redwood + "/color/" + n + ".jpg");
    fs::create_symlink("/nonexistent/x.jpg", redwood + "/color/" + n + ".jpg");
  }
  e = errorOf([&] { FrameListSource s(readRedwood(redwood)); });
  EXPECT_TRUE(contains(e, redwood + "/color/000000.jpg is a link to /nonexistent/x.jpg")) << e;
}

// Cause 19: intrinsics files that cannot be fused were reported by the pipeline as
// "Intrinsics.cx (--intrinsics)", naming neither the file nor the problem's source.
TEST(LayoutIntrinsics, ACameraThatCannotBeFusedNamesItsFile) {
  const std::string seven = test::tempDir("hostile_k_7scenes");
  test::writeSevenScenes(seven, test::fixturePoses(2));
  test::writeText(seven + "/camera-intrinsics.txt", "60 0 3200\n0 60 23.5\n0 0 1\n");
  std::string e = errorOf([&] { FrameListSource s(readSevenScenes(seven)); });
  EXPECT_TRUE(contains(e, seven + "/camera-intrinsics.txt: cx = 3200 lies outside the 64-pixel-wide image")) << e;

  const std::string dir = test::tempDir("hostile_k_replica");
  const std::string replica = test::writeReplica(dir, test::fixturePoses(2));
  test::writeText(dir + "/cam_params.json", "{\"camera\": {\"w\": 64, \"h\": 48, \"fx\": 60.0, \"fy\": 0.01, "
                                            "\"cx\": 31.5, \"cy\": 23.5, \"scale\": 6553.5}}");
  e = errorOf([&] { FrameListSource s(readReplica(replica)); });
  EXPECT_TRUE(contains(e, dir + "/cam_params.json: fy = 0.01 is out of range")) << e;

  const std::string scannet = test::tempDir("hostile_k_scannet");
  test::writeScanNet(scannet, test::fixturePoses(2));
  test::writeText(scannet + "/intrinsic/intrinsic_depth.txt", "60 0 31.5 0\n0 60 -5 0\n0 0 1 0\n0 0 0 1\n");
  e = errorOf([&] { FrameListSource s(readScanNet(scannet)); });
  EXPECT_TRUE(contains(e, "intrinsic_depth.txt: cy = -5 lies outside the 48-pixel-high image")) << e;
}

// Cause 24: a NaN or inf in a pose file made a frame without a pose, reported by the pipeline
// without the file. Only ScanNet's all -inf matrix (tracking lost) means no pose.
TEST(PoseFiles, NonFiniteNumbersAreRefusedNamingFileRowAndColumn) {
  const std::string seven = test::tempDir("hostile_nan_7scenes");
  test::writeSevenScenes(seven, test::fixturePoses(3));
  test::writeText(seven + "/frame-000001.pose.txt", "1 0 0 0\n0 1 0 nan\n0 0 1 0\n0 0 0 1\n");
  std::string e = errorOf([&] { readSevenScenes(seven); });
  EXPECT_TRUE(contains(e, seven + "/frame-000001.pose.txt: the pose holds nan at row 2, column 4")) << e;
  test::writeText(seven + "/frame-000001.pose.txt", "1 0 0 inf\n0 1 0 0\n0 0 1 0\n0 0 0 1\n");
  e = errorOf([&] { readSevenScenes(seven); });
  EXPECT_TRUE(contains(e, "frame-000001.pose.txt: the pose holds inf at row 1, column 4")) << e;

  const double lost[16] = {-INFINITY, -INFINITY, -INFINITY, -INFINITY, -INFINITY, -INFINITY, -INFINITY, -INFINITY,
                           -INFINITY, -INFINITY, -INFINITY, -INFINITY, -INFINITY, -INFINITY, -INFINITY, -INFINITY};
  EXPECT_FALSE(poseFromRowMajor(lost, "pose.txt")) << "ScanNet's lost frame: no pose, no error";
}

// Cause 26: nlohmann's "[json.exception.type_error.302] type must be number, but is string" named
// neither the file nor the field.
TEST(LayoutJson, AFieldOfTheWrongTypeIsNamedWithItsFile) {
  const std::string dir = test::tempDir("hostile_json_replica");
  const std::string replica = test::writeReplica(dir, test::fixturePoses(2));
  test::writeText(dir + "/cam_params.json", "{\"camera\": {\"w\": 64, \"h\": 48, \"fx\": \"60\", \"fy\": 60.0, "
                                            "\"cx\": 31.5, \"cy\": 23.5, \"scale\": 6553.5}}");
  std::string e = errorOf([&] { readReplica(replica); });
  EXPECT_TRUE(contains(e, dir + "/cam_params.json: 'camera.fx' must be a number, got \"60\" (a string)")) << e;
  EXPECT_FALSE(contains(e, "json.exception")) << e;
  test::writeText(dir + "/cam_params.json", "{\"camera\": {\"w\": 64.5, \"h\": 48}}");
  e = errorOf([&] { readReplica(replica); });
  EXPECT_TRUE(contains(e, "'camera.w' must be an integer from 1 to 100000, got 64.5")) << e;

  const std::string redwood = test::tempDir("hostile_json_redwood");
  test::writeRedwood(redwood, test::fixturePoses(2));
  test::writeText(redwood + "/camera-intrinsics.json",
                  "{\"width\": 64, \"height\": 48, \"intrinsic_matrix\": [60, 0, 0, 0, 60, 0, 31.5, null, 1]}");
  e = errorOf([&] { readRedwood(redwood); });
  EXPECT_TRUE(contains(e, redwood + "/camera-intrinsics.json: 'intrinsic_matrix[7]' must be a number, got null")) << e;
}

}  // namespace
}  // namespace vf
