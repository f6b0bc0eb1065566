// Record3D "EXR + JPG" export folders, written here synthetically with OpenCV.
#include <gtest/gtest.h>

#include <opencv2/imgcodecs.hpp>

#include <filesystem>
#include <fstream>

#include "core/error.h"
#include "io/record3d_export.h"
#include "test_data.h"

namespace vf {
namespace {
namespace fs = std::filesystem;

// Two frames: depth 4x3 (metres 1.0 + 0.25 x + 0.5 y, frame 1 adds 1 m), RGB 8x6 uniform colour,
// confidence 2 except pixel (0, 0) = 1.
std::string writeExport(const std::string& name) {
  enableOpenCvExr();
  const std::string dir = test::tempDir(name);
  fs::create_directories(dir + "/depth");
  fs::create_directories(dir + "/rgb");
  fs::create_directories(dir + "/conf");
  std::ofstream(dir + "/metadata.json")
      << R"({"w": 8, "h": 6, "K": [8, 0, 0, 0, 6, 0, 4, 3, 1], "fps": 10,)"
      << R"( "poses": [[0, 0, 0, 1, 0, 0, 0], [0, 0, 0, 1, 0, 0, 2]]})";
  for (int i = 0; i < 2; ++i) {
    cv::Mat depth(3, 4, CV_32FC1);
    for (int y = 0; y < 3; ++y)
      for (int x = 0; x < 4; ++x) depth.at<float>(y, x) = 1.0f + 0.25f * x + 0.5f * y + float(i);
    EXPECT_TRUE(cv::imwrite(dir + "/depth/" + std::to_string(i) + ".exr", depth));
    cv::Mat rgb(6, 8, CV_8UC3, cv::Scalar(30, 120, 200));  // BGR
    EXPECT_TRUE(cv::imwrite(dir + "/rgb/" + std::to_string(i) + ".jpg", rgb));
    cv::Mat conf(3, 4, CV_8UC1, cv::Scalar(2));
    conf.at<uint8_t>(0, 0) = 1;
    EXPECT_TRUE(cv::imwrite(dir + "/conf/" + std::to_string(i) + ".png", conf));
  }
  return dir;
}

TEST(Record3dExport, ReadsDepthColorConfidencePosesAndScalesIntrinsics) {
  const std::string dir = writeExport("r3d_export");
  Record3dExport exp(dir);
  ASSERT_EQ(exp.size(), 2);
  const Intrinsics k = exp.depthIntrinsics();
  EXPECT_EQ(k.width, 4);
  EXPECT_EQ(k.height, 3);
  EXPECT_FLOAT_EQ(k.fx, 4.f);  // 8 * 4/8
  EXPECT_FLOAT_EQ(k.fy, 3.f);  // 6 * 3/6
  EXPECT_FLOAT_EQ(k.cx, 2.f);
  EXPECT_FLOAT_EQ(k.cy, 1.5f);

  const RgbdFrame f = exp.load(1);
  EXPECT_EQ(f.name, "1");
  EXPECT_DOUBLE_EQ(f.timestamp, 0.1);
  EXPECT_FLOAT_EQ(f.depth(0, 0), 0.f);  // confidence 1 < default 2
  EXPECT_FLOAT_EQ(f.depth(3, 2), 1.0f + 0.75f + 1.0f + 1.0f);
  EXPECT_FLOAT_EQ(f.depth(1, 0), 2.25f);
  ASSERT_EQ(f.color.width(), 8);  // the metadata's RGB size, not the depth's
  ASSERT_EQ(f.color.height(), 6);
  EXPECT_NEAR(f.color(5, 3).r, 200, 3);
  EXPECT_NEAR(f.color(5, 3).g, 120, 3);
  EXPECT_NEAR(f.color(5, 3).b, 30, 3);
  ASSERT_TRUE(f.T_world_cam_given);
  EXPECT_NEAR(f.T_world_cam_given->translation().z(), 2.0, 1e-12);
  EXPECT_NEAR(f.T_world_cam_given->linear()(1, 1), -1.0, 1e-12);

  Record3dOptions all;
  all.min_confidence = 0;
  EXPECT_FLOAT_EQ(Record3dExport(dir, all).load(0).depth(0, 0), 1.0f);
}

TEST(Record3dExport, OpenRecord3dDetectsTheFormatFromThePath) {
  const std::string dir = writeExport("r3d_export_open");
  EXPECT_EQ(openRecord3d(dir)->size(), 2);
  const std::string empty = test::tempDir("r3d_export_empty");
  EXPECT_THROW(openRecord3d(empty), Error);
  EXPECT_THROW(openRecord3d(empty + "/nothing.r3d"), Error);
  VF_REQUIRE_DATA(r3d, "record3d_dance_head200.r3d");
  EXPECT_EQ(openRecord3d(r3d)->size(), 200);
}

// Issue 35, cause 10: colour of another size than metadata.json's w x h was stretched onto it.
TEST(Record3dExport, ColourOfAnotherSizeThanTheMetadataIsRefused) {
  const std::string dir = writeExport("r3d_export_rgb_size");
  EXPECT_TRUE(cv::imwrite(dir + "/rgb/0.jpg", cv::Mat(8, 6, CV_8UC3, cv::Scalar(30, 120, 200))));
  const std::string e = test::errorOf([&] { Record3dExport(dir).load(0); });
  EXPECT_NE(e.find(dir + "/rgb/0.jpg: the colour image is 6x8 but the metadata says w x h = 8x6"), std::string::npos)
      << e;
}

TEST(Record3dExport, MissingOrInconsistentFilesThrowNamingThem) {
  const std::string dir = writeExport("r3d_export_bad");
  fs::remove(dir + "/rgb/1.jpg");
  try {
    Record3dExport(dir).load(1);
    FAIL();
  } catch (const Error& e) {
    EXPECT_NE(std::string(e.what()).find("rgb/1.png"), std::string::npos) << e.what();
  }
  std::ofstream(dir + "/depth/1.exr") << "not an exr";
  try {
    Record3dExport(dir).load(1);
    FAIL();
  } catch (const Error& e) {
    EXPECT_NE(std::string(e.what()).find("depth/1.exr"), std::string::npos) << e.what();
  }
}

}  // namespace
}  // namespace vf
