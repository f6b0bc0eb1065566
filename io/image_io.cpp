#include "io/image_io.h"

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <filesystem>
#include <opencv2/imgcodecs.hpp>
#include <opencv2/imgproc.hpp>
#include <string>
#include <vector>

#include "core/atomic_output.h"

namespace vf {
namespace {

namespace fs = std::filesystem;

std::string describeType(const cv::Mat& m) {
  const int bits = m.depth() == CV_8U ? 8 : m.depth() == CV_16U ? 16 : m.depth() == CV_32F ? 32 : 0;
  return std::to_string(bits) + "-bit " + std::to_string(m.channels()) + "-channel";
}

cv::Mat readUnchanged(const std::string& path, const char* what) {
  if (!fs::exists(path)) throw Error(std::string(what) + " not found: " + path);
  cv::Mat m = cv::imread(path, cv::IMREAD_UNCHANGED);
  if (m.empty())
    throw Error("cannot decode " + std::string(what) + " " + path +
                " (not a PNG/JPG OpenCV can read, or truncated)");
  return m;
}

void encodeAndWrite(const std::string& path, const cv::Mat& image) {
  std::vector<uchar> buffer;
  // Encode to memory first: the temp file then always has the full PNG, whatever its name.
  if (!cv::imencode(".png", image, buffer)) throw Error("cannot encode PNG for " + path);
  writeFileAtomic(path, std::string(buffer.begin(), buffer.end()));
}

}  // namespace

DepthImage readDepthPng(const std::string& path, float units_per_metre) {
  if (!(units_per_metre > 0)) throw Error("depth scale must be positive, got " + std::to_string(units_per_metre));
  const cv::Mat m = readUnchanged(path, "depth image");
  if (m.type() != CV_16UC1)
    throw Error("depth image " + path + " is " + describeType(m) +
                "; depth must be a 16-bit single-channel PNG (value / " +
                std::to_string(int(units_per_metre)) + " = metres)");
  DepthImage depth(m.cols, m.rows);
  const float inv = 1.f / units_per_metre;
  for (int y = 0; y < m.rows; ++y) {
    const uint16_t* row = m.ptr<uint16_t>(y);
    float* out = depth.data() + size_t(y) * m.cols;
    for (int x = 0; x < m.cols; ++x) out[x] = float(row[x]) * inv;
  }
  return depth;
}

ColorImage readColorImage(const std::string& path) {
  cv::Mat m = readUnchanged(path, "colour image");
  if (m.depth() == CV_16U) m.convertTo(m, CV_8U, 1.0 / 257.0);
  if (m.depth() != CV_8U) throw Error("colour image " + path + " is " + describeType(m) + "; expected 8 or 16 bit");
  cv::Mat rgba;
  switch (m.channels()) {
    case 1: cv::cvtColor(m, rgba, cv::COLOR_GRAY2RGBA); break;
    case 3: cv::cvtColor(m, rgba, cv::COLOR_BGR2RGBA); break;
    case 4: cv::cvtColor(m, rgba, cv::COLOR_BGRA2RGBA); break;
    default: throw Error("colour image " + path + " has " + std::to_string(m.channels()) + " channels");
  }
  ColorImage color(rgba.cols, rgba.rows);
  for (int y = 0; y < rgba.rows; ++y) {
    const cv::Vec4b* row = rgba.ptr<cv::Vec4b>(y);
    Rgb8* out = color.data() + size_t(y) * rgba.cols;
    for (int x = 0; x < rgba.cols; ++x) out[x] = {row[x][0], row[x][1], row[x][2], 255};
  }
  return color;
}

LabelImage readLabelPng(const std::string& path) {
  const cv::Mat m = readUnchanged(path, "label map");
  if (m.channels() != 1 || (m.depth() != CV_8U && m.depth() != CV_16U))
    throw Error("label map " + path + " is " + describeType(m) +
                "; label maps must be single-channel 8- or 16-bit PNGs of class ids (not colour-coded)");
  LabelImage labels(m.cols, m.rows);
  for (int y = 0; y < m.rows; ++y) {
    uint16_t* out = labels.data() + size_t(y) * m.cols;
    if (m.depth() == CV_8U) {
      const uint8_t* row = m.ptr<uint8_t>(y);
      for (int x = 0; x < m.cols; ++x) out[x] = row[x];
    } else {
      const uint16_t* row = m.ptr<uint16_t>(y);
      for (int x = 0; x < m.cols; ++x) out[x] = row[x];
    }
  }
  return labels;
}

void writeDepthPng(const std::string& path, const DepthImage& depth_m, float units_per_metre) {
  if (depth_m.empty()) throw Error("cannot write empty depth image to " + path);
  cv::Mat m(depth_m.height(), depth_m.width(), CV_16UC1);
  for (int y = 0; y < m.rows; ++y) {
    uint16_t* row = m.ptr<uint16_t>(y);
    for (int x = 0; x < m.cols; ++x) {
      const float d = depth_m(x, y);
      const float v = std::isfinite(d) && d > 0 ? std::round(d * units_per_metre) : 0.f;
      row[x] = uint16_t(std::min(v, 65535.f));
    }
  }
  encodeAndWrite(path, m);
}

void writeColorPng(const std::string& path, const ColorImage& color) {
  if (color.empty()) throw Error("cannot write empty colour image to " + path);
  cv::Mat m(color.height(), color.width(), CV_8UC3);
  for (int y = 0; y < m.rows; ++y) {
    cv::Vec3b* row = m.ptr<cv::Vec3b>(y);
    for (int x = 0; x < m.cols; ++x) {
      const Rgb8 c = color(x, y);
      row[x] = {c.b, c.g, c.r};  // OpenCV stores BGR
    }
  }
  encodeAndWrite(path, m);
}

void writeLabelPng(const std::string& path, const LabelImage& labels) {
  if (labels.empty()) throw Error("cannot write empty label map to " + path);
  uint16_t max_id = 0;
  for (int i = 0; i < labels.width() * labels.height(); ++i) max_id = std::max(max_id, labels.data()[i]);
  cv::Mat m(labels.height(), labels.width(), max_id < 256 ? CV_8UC1 : CV_16UC1);
  for (int y = 0; y < m.rows; ++y)
    for (int x = 0; x < m.cols; ++x) {
      if (max_id < 256)
        m.at<uint8_t>(y, x) = uint8_t(labels(x, y));
      else
        m.at<uint16_t>(y, x) = labels(x, y);
    }
  encodeAndWrite(path, m);
}

}  // namespace vf
