// io/png_inflate.h, the libdeflate path of the PNG decoder: real frames take it and decode to
// OpenCV's pixels; every filter type at every bytes-per-pixel it serves undoes to the rows
// written; and a file it must not finish (damaged, or a layout it leaves to libpng) falls back
// to libpng, which decodes it or refuses it with its own words.
#include <gtest/gtest.h>
#include <zlib.h>

#include <algorithm>
#include <cstring>
#include <filesystem>
#include <fstream>
#include <string>
#include <vector>

#include "io/image_codec.h"
#include "io/image_io.h"
#include "io/png_inflate.h"
#include "opencv_reference.h"
#include "png_builder.h"
#include "test_data.h"

namespace vf {
namespace {

namespace fs = std::filesystem;
using png_inflate::Layout;

std::string firstPng(const std::string& dir, const std::string& suffix = ".png") {
  std::vector<std::string> files;
  for (const auto& e : fs::directory_iterator(dir)) {
    const std::string name = e.path().filename().string();
    if (name.size() > suffix.size() && name.compare(name.size() - suffix.size(), suffix.size(), suffix) == 0)
      files.push_back(e.path().string());
  }
  std::sort(files.begin(), files.end());
  return files.empty() ? std::string() : files[0];
}

bool inflates(const std::string& bytes, Layout layout, png_inflate::Rows* rows = nullptr) {
  png_inflate::Rows ignored;
  return png_inflate::decode(reinterpret_cast<const uint8_t*>(bytes.data()), bytes.size(), layout, kMaxImagePixels,
                             rows ? *rows : ignored);
}

void writeFile(const std::string& path, const std::string& bytes) {
  std::ofstream(path, std::ios::binary).write(bytes.data(), std::streamsize(bytes.size()));
}

std::string fileText(const std::string& path) {
  const std::vector<uint8_t> bytes = readFileBytes(path, "test file");
  return std::string(bytes.begin(), bytes.end());
}

// The rows as stored, from OpenCV (IMREAD_UNCHANGED gives BGR order and native-endian samples).
std::string storedRows(const std::string& path) {
  cv::Mat m = test::opencvRead(path);
  if (m.channels() == 3) cv::cvtColor(m, m, cv::COLOR_BGR2RGB);
  if (m.channels() == 4) cv::cvtColor(m, m, cv::COLOR_BGRA2RGBA);
  std::string rows;
  for (int y = 0; y < m.rows; ++y) {
    const uint8_t* row = m.ptr<uint8_t>(y);
    const size_t n = size_t(m.cols) * m.elemSize();
    if (m.elemSize1() == 1) {
      rows.append(reinterpret_cast<const char*>(row), n);
    } else {
      for (size_t i = 0; i < n; i += 2) rows += std::string{char(row[i + 1]), char(row[i])};  // big-endian
    }
  }
  return rows;
}

std::string rowsOf(const png_inflate::Rows& rows) {
  std::string out;
  for (int y = 0; y < rows.height; ++y) out.append(reinterpret_cast<const char*>(rows.row(y)), rows.row_bytes);
  return out;
}

TEST(PngInflate, RealFramesTakeThisPathAndDecodeToOpenCvsPixels) {
  struct Frame {
    const char* capture;
    const char* folder;
    const char* suffix;
    Layout layout;
  };
  // TUM writes the Sub filter on every row, Replica the Paeth filter; 7-Scenes depth in mm.
  for (const Frame& f : {Frame{"tum_fr1_xyz_head100", "depth", ".png", Layout::Grey16},
                         Frame{"tum_fr1_xyz_head100", "rgb", ".png", Layout::Rgb8},
                         Frame{"tum_fr3_teddy_head60", "rgb", ".png", Layout::Rgb8},
                         Frame{"replica_office0", "office0/results", ".png", Layout::Grey16},
                         Frame{"7scenes_redkitchen_head100", "", ".depth.png", Layout::Grey16}}) {
    VF_REQUIRE_DATA(dir, f.capture);
    const std::string path = firstPng(dir + "/" + f.folder, f.suffix);
    ASSERT_FALSE(path.empty()) << dir << "/" << f.folder;
    SCOPED_TRACE(path);
    png_inflate::Rows rows;
    ASSERT_TRUE(inflates(fileText(path), f.layout, &rows));
    EXPECT_TRUE(rowsOf(rows) == storedRows(path));
    EXPECT_FALSE(inflates(fileText(path), f.layout == Layout::Rgb8 ? Layout::Rgba8 : Layout::Grey8));
  }
}

TEST(PngInflate, EveryFilterAtEveryPixelSizeUndoesToTheRowsWritten) {
  struct Kind {
    int bit_depth, color_type, bytes_per_pixel;
    Layout layout;
  };
  const int width = 61, height = 25;  // filter (y + first) % 5 on row y: each type next to the others
  for (const Kind& k : {Kind{8, 0, 1, Layout::Grey8}, Kind{16, 0, 2, Layout::Grey16}, Kind{8, 2, 3, Layout::Rgb8},
                        Kind{8, 6, 4, Layout::Rgba8}}) {
    SCOPED_TRACE(k.bytes_per_pixel);
    // Noise on the left (Paeth's ties between its candidates come up), a gradient on the right.
    std::string rows;
    uint32_t noise = 12345;
    for (int y = 0; y < height; ++y)
      for (int i = 0; i < width * k.bytes_per_pixel; ++i) {
        noise = noise * 1664525u + 1013904223u;
        rows += char(i < width * k.bytes_per_pixel / 2 ? uint8_t(noise >> 24) : uint8_t(y * 3 + i));
      }
    for (int first_filter = 0; first_filter < 5; ++first_filter) {
      const std::string png = test::makePng(width, height, k.bit_depth, k.color_type, rows, "", "",
                                            [&](int y) { return (y + first_filter) % 5; });
      png_inflate::Rows out;
      ASSERT_TRUE(inflates(png, k.layout, &out)) << first_filter;
      EXPECT_EQ(out.width, width);
      EXPECT_EQ(out.height, height);
      EXPECT_TRUE(rowsOf(out) == rows) << "first row's filter " << first_filter;
    }
  }
}

TEST(PngInflate, WhatThisPathLeavesDecodesOrFailsThroughLibpng) {
  VF_REQUIRE_DATA(tum, "tum_fr3_teddy_head60");
  const std::string dir = test::tempDir("png_inflate_fallback");
  const std::string depth_path = firstPng(tum + "/depth");
  const std::string depth = fileText(depth_path);
  ASSERT_TRUE(inflates(depth, Layout::Grey16));
  const size_t idat = depth.find("IDAT");
  ASSERT_NE(idat, std::string::npos);

  // Damage libpng refuses: a flipped pixel byte (IDAT CRC), no IEND, a CRC-correct IDAT whose
  // stream inflates wrong. Each is refused here and by the reader, naming the file.
  std::string flipped = depth;
  flipped[idat + 40] = char(flipped[idat + 40] ^ 0x10);
  std::string no_end = depth.substr(0, depth.size() - 12);
  std::string bad_filter_rows;  // 8 x 4 16-bit grey, row 0 with filter byte 7
  for (int y = 0; y < 4; ++y) bad_filter_rows += char(y == 0 ? 7 : 0) + std::string(16, '\x01');
  const std::string bad_filter = test::makePngOfRawRows(8, 4, 16, 0, bad_filter_rows);
  struct Damaged {
    const char* name;
    const std::string* bytes;
  };
  for (const Damaged& d : {Damaged{"flipped.png", &flipped}, Damaged{"no_end.png", &no_end},
                           Damaged{"bad_filter.png", &bad_filter}}) {
    SCOPED_TRACE(d.name);
    EXPECT_FALSE(inflates(*d.bytes, Layout::Grey16));
    const std::string path = dir + "/" + d.name;
    writeFile(path, *d.bytes);
    const std::string error = test::errorOf([&] { readDepthPng(path); });
    EXPECT_NE(error.find(path), std::string::npos) << error;
    EXPECT_NE(error.find("cannot decode"), std::string::npos) << error;
  }

  // Layouts left to libpng decode as before: RGB with a tRNS chunk (an alpha channel to OpenCV),
  // and an unknown ancillary chunk is skipped here as libpng skips it.
  std::string rgb_rows;
  for (int i = 0; i < 6 * 5 * 3; ++i) rgb_rows += char(i * 5);
  const std::string trns = test::makePng(6, 5, 8, 2, rgb_rows, "", std::string("\x00\x00\x00\x00\x00\x00", 6));
  EXPECT_FALSE(inflates(trns, Layout::Rgb8));
  writeFile(dir + "/trns.png", trns);
  EXPECT_EQ(readColorImage(dir + "/trns.png")(1, 0).r, 15);
  std::string with_text = test::makePng(6, 5, 8, 2, rgb_rows);
  std::string chunk;
  test::appendChunk(chunk, "tEXt", std::string("Comment\0made by hand", 20));
  with_text.insert(33, chunk);  // after the signature and IHDR
  png_inflate::Rows out;
  ASSERT_TRUE(inflates(with_text, Layout::Rgb8, &out));
  EXPECT_TRUE(rowsOf(out) == rgb_rows);
}

}  // namespace
}  // namespace vf
