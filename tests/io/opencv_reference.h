#pragma once
// The frame readers as they were on OpenCV (cv::imread IMREAD_UNCHANGED, cvtColor, convertTo), kept
// as the oracle that io/image_codec.h must match pixel for pixel and the baseline its speed is
// measured against (image_decode_bench). Tests only.
#include <opencv2/imgcodecs.hpp>
#include <opencv2/imgproc.hpp>
#include <string>

#include "core/error.h"
#include "core/image.h"

namespace vf::test {

inline cv::Mat opencvRead(const std::string& path) {
  cv::Mat m = cv::imread(path, cv::IMREAD_UNCHANGED);
  if (m.empty()) throw Error("OpenCV cannot decode " + path);
  return m;
}

inline DepthImage opencvDepth(const std::string& path, float units_per_metre = 5000.f) {
  const cv::Mat m = opencvRead(path);
  if (m.type() != CV_16UC1) throw Error(path + " is not 16-bit single-channel");
  DepthImage depth(m.cols, m.rows);
  const float inv = 1.f / units_per_metre;
  for (int y = 0; y < m.rows; ++y) {
    const uint16_t* row = m.ptr<uint16_t>(y);
    float* out = depth.data() + size_t(y) * m.cols;
    for (int x = 0; x < m.cols; ++x) out[x] = float(row[x]) * inv;
  }
  return depth;
}

inline ColorImage opencvColor(const std::string& path) {
  cv::Mat m = opencvRead(path);
  if (m.depth() == CV_16U) m.convertTo(m, CV_8U, 1.0 / 257.0);
  cv::Mat rgba;
  switch (m.channels()) {
    case 1: cv::cvtColor(m, rgba, cv::COLOR_GRAY2RGBA); break;
    case 3: cv::cvtColor(m, rgba, cv::COLOR_BGR2RGBA); break;
    case 4: cv::cvtColor(m, rgba, cv::COLOR_BGRA2RGBA); break;
    default: throw Error(path + ": unexpected channel count");
  }
  ColorImage color(rgba.cols, rgba.rows);
  for (int y = 0; y < rgba.rows; ++y) {
    const cv::Vec4b* row = rgba.ptr<cv::Vec4b>(y);
    Rgb8* out = color.data() + size_t(y) * rgba.cols;
    for (int x = 0; x < rgba.cols; ++x) out[x] = {row[x][0], row[x][1], row[x][2], 255};
  }
  return color;
}

}  // namespace vf::test
