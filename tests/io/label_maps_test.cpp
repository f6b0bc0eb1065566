#include <gtest/gtest.h>

#include "io/image_io.h"
#include "io/label_maps.h"
#include "test_data.h"

namespace vf {
namespace {

// A 720x960 map whose source pixel (sx, sy) holds the id of the 192x256 cell it falls in:
// floor(sx * 192 / 720) + 192 * floor(sy * 256 / 960). Nearest-neighbour sampling at output pixel
// centres must then give exactly x + 192 * y, at a non-integer ratio of 3.75.
LabelImage craftedRecord3dMap() {
  LabelImage map(720, 960);
  for (int sy = 0; sy < 960; ++sy)
    for (int sx = 0; sx < 720; ++sx) map(sx, sy) = uint16_t(sx * 192 / 720 + 192 * (sy * 256 / 960));
  return map;
}

TEST(LabelMaps, Resample720x960To192x256PicksTheCellOfEachPixel) {
  const LabelImage out = resampleLabelsNearest(craftedRecord3dMap(), 192, 256);
  ASSERT_EQ(out.width(), 192);
  ASSERT_EQ(out.height(), 256);
  int wrong = 0;
  for (int y = 0; y < 256; ++y)
    for (int x = 0; x < 192; ++x) wrong += out(x, y) != uint16_t(x + 192 * y);
  EXPECT_EQ(wrong, 0);
}

TEST(LabelMaps, ResampleUpAndIntegerRatios) {
  LabelImage two(2, 2);
  two(0, 0) = 1, two(1, 0) = 2, two(0, 1) = 3, two(1, 1) = 4;
  const LabelImage up = resampleLabelsNearest(two, 6, 6);  // x3: each id becomes a 3x3 block
  EXPECT_EQ(up(2, 2), 1);
  EXPECT_EQ(up(3, 2), 2);
  EXPECT_EQ(up(2, 3), 3);
  EXPECT_EQ(up(5, 5), 4);
  const LabelImage down = resampleLabelsNearest(up, 2, 2);  // back: exact
  for (int i = 0; i < 4; ++i) EXPECT_EQ(down.data()[i], two.data()[i]);
}

TEST(LabelMaps, FindsByStemThenIndexAndResamples) {
  const std::string dir = test::tempDir("label_maps_find");
  writeLabelPng(dir + "/7.png", craftedRecord3dMap());
  LabelImage tum(8, 6, 3);
  writeLabelPng(dir + "/1305031102.160407.png", tum);
  const LabelMapDir maps(dir);

  const LabelLookup by_index = maps.load("frame_without_map", 7, 192, 256);
  ASSERT_TRUE(by_index.labels.has_value());
  EXPECT_EQ(by_index.path, dir + "/7.png");
  EXPECT_EQ((*by_index.labels)(191, 255), 191 + 192 * 255);

  const LabelLookup by_stem = maps.load("1305031102.160407", 0, 8, 6);
  ASSERT_TRUE(by_stem.labels.has_value());
  EXPECT_EQ(by_stem.path, dir + "/1305031102.160407.png");
  EXPECT_EQ((*by_stem.labels)(4, 4), 3);

  const LabelLookup missing = maps.load("nope", 8, 192, 256);
  EXPECT_FALSE(missing.labels.has_value());
  EXPECT_EQ(missing.path, dir + "/nope.png");
}

TEST(LabelMaps, ColourMapAndMissingFolderAreErrors) {
  const std::string dir = test::tempDir("label_maps_colour");
  writeColorPng(dir + "/0.png", ColorImage(4, 4, Rgb8{1, 2, 3, 255}));
  const LabelMapDir maps(dir);
  try {
    maps.load("x", 0, 4, 4);
    FAIL() << "a 3-channel label map must be rejected";
  } catch (const Error& e) {
    EXPECT_NE(std::string(e.what()).find(dir + "/0.png"), std::string::npos) << e.what();
  }
  EXPECT_THROW(LabelMapDir(dir + "/absent"), Error);
  // A rotated map (960 wide, 720 high) must not be stretched onto a 192x256 frame.
  writeLabelPng(dir + "/1.png", LabelImage(960, 720, 1));
  EXPECT_THROW(maps.load("x", 1, 192, 256), Error);
}

TEST(LabelMaps, RealDanceMasksLoadAtDepthResolution) {
  VF_REQUIRE_DATA(dir, "record3d_dance_head200_labels");
  const LabelMapDir maps(dir);
  const LabelLookup l = maps.load("0", 0, 192, 256);
  ASSERT_TRUE(l.labels.has_value()) << l.path;
  int person = 0, other = 0;
  for (int i = 0; i < 192 * 256; ++i) {
    const uint16_t id = l.labels->data()[i];
    person += id == 1;
    other += id > 1;
  }
  EXPECT_EQ(other, 0);  // ids are 0/1 only
  // A dancer fills a visible part of the frame but not all of it.
  EXPECT_GT(person, 192 * 256 / 50);
  EXPECT_LT(person, 192 * 256 * 9 / 10);
}

}  // namespace
}  // namespace vf
