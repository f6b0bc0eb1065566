// image_decode_bench: io/image_codec.h (what readDepthPng / readColorImage use) against the
// OpenCV readers it replaced (cv::imread + conversions, tests/io/opencv_reference.h), on a TUM
// folder's PNGs. Each file is decoded by both in turn, `rounds` times after one warm-up pass (the
// files then come from the page cache); prints the median and mean ms per image.
//
//   image_decode_bench TUM_FOLDER [ROUNDS (default 5)]
#include <algorithm>
#include <chrono>
#include <cstdio>
#include <cstdlib>
#include <filesystem>
#include <functional>
#include <string>
#include <vector>

#include "core/error.h"
#include "io/image_io.h"
#include "opencv_reference.h"

namespace {

namespace fs = std::filesystem;

std::vector<std::string> pngs(const std::string& dir) {
  std::vector<std::string> files;
  for (const auto& e : fs::directory_iterator(dir))
    if (e.path().extension() == ".png") files.push_back(e.path().string());
  std::sort(files.begin(), files.end());
  if (files.empty()) throw vf::Error("no PNG files in " + dir);
  return files;
}

double timeMs(const std::function<void()>& f) {
  const auto start = std::chrono::steady_clock::now();
  f();
  return std::chrono::duration<double, std::milli>(std::chrono::steady_clock::now() - start).count();
}

void report(const char* what, std::vector<double> ms) {
  std::sort(ms.begin(), ms.end());
  double mean = 0;
  for (double v : ms) mean += v / double(ms.size());
  std::printf("  %-26s median %7.3f ms  mean %7.3f ms  (%zu decodes)\n", what, ms[ms.size() / 2], mean, ms.size());
}

}  // namespace

int main(int argc, char** argv) {
  if (argc < 2 || argc > 3) {
    std::fprintf(stderr, "usage: image_decode_bench TUM_FOLDER [ROUNDS]\n");
    return 2;
  }
  const int rounds = argc == 3 ? std::max(1, std::atoi(argv[2])) : 5;
  try {
    const std::vector<std::string> depth = pngs(std::string(argv[1]) + "/depth");
    const std::vector<std::string> rgb = pngs(std::string(argv[1]) + "/rgb");
    std::vector<double> codec_depth, cv_depth, codec_rgb, cv_rgb;
    for (int round = 0; round <= rounds; ++round) {
      for (const std::string& f : depth) {
        const double a = timeMs([&] { vf::readDepthPng(f); });
        const double b = timeMs([&] { vf::test::opencvDepth(f); });
        if (round > 0) codec_depth.push_back(a), cv_depth.push_back(b);
      }
      for (const std::string& f : rgb) {
        const double a = timeMs([&] { vf::readColorImage(f); });
        const double b = timeMs([&] { vf::test::opencvColor(f); });
        if (round > 0) codec_rgb.push_back(a), cv_rgb.push_back(b);
      }
    }
    std::printf("%s: %zu depth and %zu colour PNGs, %d rounds\n", argv[1], depth.size(), rgb.size(), rounds);
    std::printf("depth (16-bit grey PNG -> metres):\n");
    report("image_codec", codec_depth);
    report("OpenCV imread + convert", cv_depth);
    std::printf("colour (8-bit RGB PNG -> RGBA):\n");
    report("image_codec", codec_rgb);
    report("OpenCV imread + cvtColor", cv_rgb);
    return 0;
  } catch (const vf::Error& e) {
    std::fprintf(stderr, "image_decode_bench: %s\n", e.what());
    return 1;
  }
}
