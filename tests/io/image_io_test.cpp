#include <gtest/gtest.h>

#include <filesystem>
#include <fstream>

#include "io/image_io.h"
#include "test_data.h"

namespace vf {
namespace {

namespace fs = std::filesystem;

TEST(ImageIo, DepthRoundTripKeepsMetresToTheUnit) {
  const std::string dir = test::tempDir("image_io_depth");
  DepthImage depth(4, 3, 0.f);
  depth(0, 0) = 1.2346f;   // 6173 units of 0.2 mm
  depth(3, 2) = 0.5f;      // 2500
  depth(1, 1) = -1.f;      // invalid -> 0
  depth(2, 1) = 20.f;      // beyond 13.107 m -> clamped to 65535
  writeDepthPng(dir + "/d.png", depth);
  const DepthImage back = readDepthPng(dir + "/d.png");
  ASSERT_EQ(back.width(), 4);
  ASSERT_EQ(back.height(), 3);
  EXPECT_FLOAT_EQ(back(0, 0), 6173.f / 5000.f);
  EXPECT_FLOAT_EQ(back(3, 2), 0.5f);
  EXPECT_EQ(back(1, 1), 0.f);
  EXPECT_FLOAT_EQ(back(2, 1), 65535.f / 5000.f);
  EXPECT_EQ(back(2, 2), 0.f);
  // No temporary file is left beside the target.
  int files = 0;
  for (const auto& e : fs::directory_iterator(dir)) files += e.is_regular_file();
  EXPECT_EQ(files, 1);
}

TEST(ImageIo, EightBitDepthIsRejectedNamingTheFile) {
  const std::string dir = test::tempDir("image_io_8bit");
  LabelImage eight_bit(5, 5, 7);  // ids < 256 are written as an 8-bit PNG
  writeLabelPng(dir + "/depth8.png", eight_bit);
  try {
    readDepthPng(dir + "/depth8.png");
    FAIL() << "an 8-bit depth PNG must be rejected";
  } catch (const Error& e) {
    const std::string msg = e.what();
    EXPECT_NE(msg.find(dir + "/depth8.png"), std::string::npos) << msg;
    EXPECT_NE(msg.find("16-bit"), std::string::npos) << msg;
  }
  ColorImage color(5, 5, Rgb8{1, 2, 3, 255});
  writeColorPng(dir + "/rgb.png", color);
  EXPECT_THROW(readDepthPng(dir + "/rgb.png"), Error);
}

TEST(ImageIo, ColorRoundTripAndChannelOrder) {
  const std::string dir = test::tempDir("image_io_color");
  ColorImage color(2, 2, Rgb8{10, 20, 30, 255});
  color(1, 0) = {255, 0, 0, 255};
  writeColorPng(dir + "/c.png", color);
  const ColorImage back = readColorImage(dir + "/c.png");
  EXPECT_EQ(back(1, 0).r, 255);
  EXPECT_EQ(back(1, 0).g, 0);
  EXPECT_EQ(back(1, 0).b, 0);
  EXPECT_EQ(back(0, 1).r, 10);
  EXPECT_EQ(back(0, 1).g, 20);
  EXPECT_EQ(back(0, 1).b, 30);
  EXPECT_EQ(back(0, 1).a, 255);
}

TEST(ImageIo, LabelsRoundTripIn8And16Bit) {
  const std::string dir = test::tempDir("image_io_labels");
  LabelImage small(3, 2, 0), large(3, 2, 0);
  small(2, 1) = 149;
  large(2, 1) = 1000;
  writeLabelPng(dir + "/s.png", small);
  writeLabelPng(dir + "/l.png", large);
  EXPECT_EQ(readLabelPng(dir + "/s.png")(2, 1), 149);
  EXPECT_EQ(readLabelPng(dir + "/l.png")(2, 1), 1000);
}

TEST(ImageIo, MissingAndCorruptFilesNameThePath) {
  const std::string dir = test::tempDir("image_io_missing");
  try {
    readColorImage(dir + "/nothing.png");
    FAIL();
  } catch (const Error& e) {
    EXPECT_NE(std::string(e.what()).find(dir + "/nothing.png"), std::string::npos);
  }
  std::ofstream(dir + "/bad.png") << "not a png";
  try {
    readDepthPng(dir + "/bad.png");
    FAIL();
  } catch (const Error& e) {
    EXPECT_NE(std::string(e.what()).find(dir + "/bad.png"), std::string::npos);
  }
}

TEST(ImageIo, RealTumDepthIs16BitMetres) {
  VF_REQUIRE_DATA(path, "tum_fr1_xyz_head100/depth/1305031102.160407.png");
  const DepthImage depth = readDepthPng(path);
  EXPECT_EQ(depth.width(), 640);
  EXPECT_EQ(depth.height(), 480);
}

}  // namespace
}  // namespace vf
