// io/image_codec.h (libpng, libjpeg-turbo) against OpenCV's readers it replaced: the same pixels
// on real TUM and 7-Scenes frames and on every PNG/JPEG layout the readers accept, and refusals
// (naming the file) of truncated files and of headers too large to allocate.
#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <cstring>
#include <filesystem>
#include <fstream>
#include <opencv2/imgcodecs.hpp>
#include <string>
#include <vector>

#include "io/image_codec.h"
#include "io/image_io.h"
#include "opencv_reference.h"
#include "png_builder.h"
#include "test_data.h"

namespace vf {
namespace {

namespace fs = std::filesystem;

template <class T>
bool samePixels(const Image<T>& a, const Image<T>& b) {
  return a.width() == b.width() && a.height() == b.height() &&
         std::memcmp(a.data(), b.data(), sizeof(T) * size_t(a.width()) * a.height()) == 0;
}

std::vector<std::string> firstFiles(const std::string& dir, const std::string& extension, size_t count) {
  std::vector<std::string> files;
  for (const auto& e : fs::directory_iterator(dir))
    if (e.path().extension() == extension) files.push_back(e.path().string());
  std::sort(files.begin(), files.end());
  if (files.size() > count) files.resize(count);
  return files;
}

std::vector<uint8_t> bytesOf(const std::string& path) { return readFileBytes(path, "test file"); }

void writeBytes(const std::string& path, const uint8_t* data, size_t size) {
  std::ofstream(path, std::ios::binary).write(reinterpret_cast<const char*>(data), std::streamsize(size));
}

bool contains(const std::string& text, const std::string& part) { return text.find(part) != std::string::npos; }

using test::makePng;

void writeString(const std::string& path, const std::string& bytes) {
  writeBytes(path, reinterpret_cast<const uint8_t*>(bytes.data()), bytes.size());
}

TEST(ImageCodec, RealTumPngsDecodeToTheSamePixelsAsOpenCv) {
  for (const char* capture : {"tum_fr1_xyz_head100", "tum_fr3_teddy_head60"}) {
    VF_REQUIRE_DATA(dir, capture);
    for (const std::string& path : firstFiles(dir + "/depth", ".png", 8))
      EXPECT_TRUE(samePixels(readDepthPng(path), test::opencvDepth(path))) << path;
    for (const std::string& path : firstFiles(dir + "/rgb", ".png", 8))
      EXPECT_TRUE(samePixels(readColorImage(path), test::opencvColor(path))) << path;
  }
}

TEST(ImageCodec, RealJpegsDecodeToTheSamePixelsAsOpenCv) {
  VF_REQUIRE_DATA(dir, "7scenes_redkitchen_head100");
  const std::vector<std::string> files = firstFiles(dir, ".jpg", 6);
  ASSERT_EQ(files.size(), 6u);
  for (const std::string& path : files) EXPECT_TRUE(samePixels(readColorImage(path), test::opencvColor(path))) << path;
}

// Every layout readColorImage / readLabelPng take, written by OpenCV (or hand-made: palette,
// grey + alpha), decodes as OpenCV decodes it.
TEST(ImageCodec, EveryAcceptedLayoutMatchesOpenCv) {
  const std::string dir = test::tempDir("image_codec_layouts");
  cv::Mat grey8(37, 53, CV_8UC1), grey16(37, 53, CV_16UC1), bgr8(37, 53, CV_8UC3), bgr16(37, 53, CV_16UC3),
      bgra8(37, 53, CV_8UC4);
  cv::randu(grey8, 0, 256);
  cv::randu(grey16, 0, 65536);
  cv::randu(bgr8, 0, 256);
  cv::randu(bgr16, 0, 65536);
  cv::randu(bgra8, 0, 256);
  std::vector<std::string> files;
  auto put = [&](const std::string& name, const cv::Mat& m) {
    ASSERT_TRUE(cv::imwrite(dir + "/" + name, m)) << name;
    files.push_back(dir + "/" + name);
  };
  put("grey8.png", grey8);
  put("grey16.png", grey16);
  put("bgr8.png", bgr8);
  put("bgr16.png", bgr16);
  put("bgra8.png", bgra8);
  put("bgr8.jpg", bgr8);
  put("grey8.jpg", grey8);
  // Layouts OpenCV does not write: palette (8- and 4-bit, with and without transparency), grey
  // with alpha, 2-bit grey, 16-bit grey with alpha.
  std::string palette, rows8, rows4, rows2, ga8, ga16;
  for (int i = 0; i < 16; ++i) palette += std::string{char(i * 16), char(255 - i * 9), char(i * i)};
  for (int i = 0; i < 7 * 10; ++i) rows8 += char(i % 16), ga8 += std::string{char(i * 3), char(i)};
  for (int i = 0; i < 4 * 10; ++i) rows4 += char((i * 37) & 0xFF), rows2 += char((i * 91) & 0xFF);
  for (int i = 0; i < 7 * 10; ++i) ga16 += std::string{char(i), char(i * 5), char(i * 7), char(3)};
  auto hand = [&](const std::string& name, const std::string& png) {
    writeString(dir + "/" + name, png);
    files.push_back(dir + "/" + name);
  };
  hand("palette8.png", makePng(7, 10, 8, 3, rows8, palette));
  hand("palette8_trns.png", makePng(7, 10, 8, 3, rows8, palette, std::string("\x00\x80\xff", 3)));
  hand("palette4.png", makePng(8, 10, 4, 3, rows4, palette));
  hand("grey2.png", makePng(16, 10, 2, 0, rows2));
  hand("ga8.png", makePng(7, 10, 8, 4, ga8));
  hand("ga16.png", makePng(7, 10, 16, 4, ga16));
  for (const char* seed : {"rgb8.png", "depth16.png", "labels8.png"})
    files.push_back(std::string(VDBFUSE_SOURCE_DIR) + "/tests/fuzz/corpus/image/" + seed);
  for (const std::string& path : files) {
    SCOPED_TRACE(path);
    EXPECT_TRUE(samePixels(readColorImage(path), test::opencvColor(path)));
    const cv::Mat m = test::opencvRead(path);
    if (path.size() > 4 && path.substr(path.size() - 4) == ".png" && m.channels() == 1) {
      const LabelImage labels = readLabelPng(path);
      ASSERT_EQ(labels.width(), m.cols);
      for (int y = 0; y < m.rows; ++y)
        for (int x = 0; x < m.cols; ++x)
          ASSERT_EQ(labels(x, y), m.depth() == CV_8U ? m.at<uint8_t>(y, x) : m.at<uint16_t>(y, x)) << x << "," << y;
    } else {
      EXPECT_TRUE(contains(test::errorOf([&] { readLabelPng(path); }), path));
    }
  }
  EXPECT_TRUE(samePixels(readDepthPng(dir + "/grey16.png"), test::opencvDepth(dir + "/grey16.png")));
  EXPECT_TRUE(contains(test::errorOf([&] { readDepthPng(dir + "/bgr16.png"); }), "16-bit 3-channel"));
  EXPECT_TRUE(contains(test::errorOf([&] { readDepthPng(dir + "/bgr8.jpg"); }), "is a JPEG"));
}

TEST(ImageCodec, TruncatedFilesAreRefusedNamingTheFile) {
  VF_REQUIRE_DATA(tum, "tum_fr3_teddy_head60");
  VF_REQUIRE_DATA(kitchen, "7scenes_redkitchen_head100");
  const std::string dir = test::tempDir("image_codec_truncated");
  const std::string depth = firstFiles(tum + "/depth", ".png", 1)[0];
  const std::string color = firstFiles(tum + "/rgb", ".png", 1)[0];
  const std::string jpeg = firstFiles(kitchen, ".jpg", 1)[0];
  struct Cut {
    std::string source;
    double keep;  // share of the file kept; 0 = all but the 12-byte IEND chunk
  };
  for (const Cut& cut : {Cut{depth, 0.6}, Cut{depth, 0.0}, Cut{color, 0.3}, Cut{jpeg, 0.6}, Cut{jpeg, 0.98}}) {
    const std::vector<uint8_t> bytes = bytesOf(cut.source);
    const size_t keep = cut.keep > 0 ? size_t(double(bytes.size()) * cut.keep) : bytes.size() - 12;
    const std::string path = dir + "/cut_" + std::to_string(keep) + fs::path(cut.source).extension().string();
    writeBytes(path, bytes.data(), keep);
    const std::string error = test::errorOf([&] { readColorImage(path); });
    EXPECT_TRUE(contains(error, path)) << error;
    EXPECT_TRUE(contains(error, "cannot decode")) << error;
    if (cut.source == depth) {
      EXPECT_TRUE(contains(test::errorOf([&] { readDepthPng(path); }), path));
    }
  }
  writeBytes(dir + "/empty.png", nullptr, 0);
  EXPECT_TRUE(contains(test::errorOf([&] { readDepthPng(dir + "/empty.png"); }), "empty"));
  std::ofstream(dir + "/text.png") << "not an image at all";
  EXPECT_TRUE(contains(test::errorOf([&] { readColorImage(dir + "/text.png"); }), "not a PNG or JPEG"));
}

TEST(ImageCodec, HeadersBeyondTheLimitOrWithoutPixelsAreRefusedBeforeAllocating) {
  const std::string dir = test::tempDir("image_codec_limits");
  // 400 Mpx (800 MB as 16-bit) claimed, a few bytes of pixel data given.
  writeString(dir + "/big.png", makePng(20000, 20000, 16, 0, ""));
  std::string error = test::errorOf([&] { readDepthPng(dir + "/big.png"); });
  EXPECT_TRUE(contains(error, dir + "/big.png")) << error;
  EXPECT_TRUE(contains(error, "400 Mpx")) << error;
  writeString(dir + "/zero.png", makePng(0, 480, 16, 0, ""));
  error = test::errorOf([&] { readDepthPng(dir + "/zero.png"); });
  EXPECT_TRUE(contains(error, dir + "/zero.png")) << error;

  // A real JPEG whose frame header claims 20000 x 20000.
  VF_REQUIRE_DATA(kitchen, "7scenes_redkitchen_head100");
  std::vector<uint8_t> jpeg = bytesOf(firstFiles(kitchen, ".jpg", 1)[0]);
  bool patched = false;
  for (size_t i = 2; i + 9 < jpeg.size() && !patched; ++i)
    if (jpeg[i] == 0xFF && (jpeg[i + 1] == 0xC0 || jpeg[i + 1] == 0xC2)) {  // SOF0 / SOF2
      jpeg[i + 5] = 0x4E, jpeg[i + 6] = 0x20, jpeg[i + 7] = 0x4E, jpeg[i + 8] = 0x20;  // height, width
      patched = true;
    }
  ASSERT_TRUE(patched);
  writeBytes(dir + "/big.jpg", jpeg.data(), jpeg.size());
  error = test::errorOf([&] { readColorImage(dir + "/big.jpg"); });
  EXPECT_TRUE(contains(error, dir + "/big.jpg")) << error;
  EXPECT_TRUE(contains(error, "400 Mpx")) << error;
}

TEST(ImageCodec, PngWritersRoundTripAndTheCompactSettingIsSmaller) {
  VF_REQUIRE_DATA(tum, "tum_fr1_xyz_head100");
  const std::string path = firstFiles(tum + "/depth", ".png", 1)[0];
  const std::vector<uint8_t> original = bytesOf(path);
  const DepthImage depth = readDepthPng(path);
  std::vector<uint16_t> units(size_t(depth.width()) * depth.height());
  for (size_t i = 0; i < units.size(); ++i) units[i] = uint16_t(depth.data()[i] * 5000.f + 0.5f);
  const std::string fast = encodePng(units.data(), depth.width(), depth.height(), 1, 16, "fast");
  const std::string small = encodePng(units.data(), depth.width(), depth.height(), 1, 16, "small", PngCompression::Compact);
  for (const std::string* png : {&fast, &small}) {
    const DepthImage back =
        decodeDepthPng(reinterpret_cast<const uint8_t*>(png->data()), png->size(), "round trip", 5000.f);
    EXPECT_TRUE(samePixels(back, depth));
  }
  EXPECT_LT(small.size(), fast.size());
  EXPECT_LT(small.size(), original.size());  // TUM's own PNGs leave room
}

TEST(ImageCodec, JpegWriterKeepsTheImageWithinAFewGreyLevels) {
  VF_REQUIRE_DATA(tum, "tum_fr3_teddy_head60");
  const ColorImage color = readColorImage(firstFiles(tum + "/rgb", ".png", 1)[0]);
  const std::string jpeg = encodeJpeg(color, 92, "teddy.jpg");
  EXPECT_LT(jpeg.size(), size_t(color.width()) * color.height() / 2);  // < 0.5 byte a pixel
  const ColorImage back = decodeColorImage(reinterpret_cast<const uint8_t*>(jpeg.data()), jpeg.size(), "teddy.jpg");
  ASSERT_EQ(back.width(), color.width());
  ASSERT_EQ(back.height(), color.height());
  double total = 0;
  for (size_t i = 0; i < size_t(color.width()) * color.height(); ++i)
    total += std::abs(back.data()[i].r - color.data()[i].r) + std::abs(back.data()[i].g - color.data()[i].g) +
             std::abs(back.data()[i].b - color.data()[i].b);
  EXPECT_LT(total / (3.0 * color.width() * color.height()), 3.0);
  EXPECT_EQ(back(5, 5).a, 255);
}

}  // namespace
}  // namespace vf
