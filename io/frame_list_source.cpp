#include "io/frame_list_source.h"

#include <algorithm>
#include <cmath>
#include <cstdio>

#include <filesystem>

#include "core/camera_check.h"
#include "core/error.h"
#include "io/image_io.h"

namespace vf {

DepthImage readScaledDepthPng(const std::string& path, float units_per_metre, uint16_t invalid_value) {
  DepthImage depth = readDepthPng(path, units_per_metre);
  if (invalid_value != 0) {
    // The decoder turns a raw value into float(raw) * (1 / units), one rounding of values that
    // lie a whole 1 / units apart: the invalid value's depth is one float that no other raw
    // value gives, so comparing floats finds exactly its pixels (an lround per pixel cost
    // 0.8 % of a 7-Scenes run).
    const float invalid_m = float(invalid_value) * (1.f / units_per_metre);
    float* d = depth.data();
    const size_t n = size_t(depth.width()) * size_t(depth.height());
    for (size_t i = 0; i < n; ++i)
      if (d[i] == invalid_m) d[i] = 0.f;
  }
  return depth;
}

namespace {

// Overlap weights of output samples over input samples along one axis: output i covers input
// [i * scale, (i + 1) * scale).
struct Tap {
  int first = 0;
  std::vector<float> weights;  // for inputs first, first + 1, ...; sum to 1
};

std::vector<Tap> areaTaps(int in_size, int out_size) {
  std::vector<Tap> taps(static_cast<size_t>(out_size));
  const double scale = double(in_size) / double(out_size);
  for (int i = 0; i < out_size; ++i) {
    const double a = i * scale, b = (i + 1) * scale;
    Tap& t = taps[size_t(i)];
    t.first = int(std::floor(a));
    for (int k = t.first; k < in_size && k < b; ++k)
      t.weights.push_back(float((std::min<double>(k + 1, b) - std::max<double>(k, a)) / scale));
  }
  return taps;
}

// Every file of the list is there before anything is fused: a dangling link where a colour image
// should be must not become a frame without colour, nor an error after an hour of fusion.
void requireFrameFile(const std::string& path, const char* what) {
  namespace fs = std::filesystem;
  std::error_code ec;
  if (fs::is_regular_file(path, ec)) return;
  if (fs::is_symlink(fs::symlink_status(path, ec)))
    throw Error(std::string(what) + " " + path + " is a link to " + fs::read_symlink(path, ec).string() +
                ", which cannot be read (missing or not a file)");
  throw Error(std::string(what) + " " + path + " is missing or not a file");
}

}  // namespace

bool aspectRatiosDiffer(int w1, int h1, int w2, int h2) {
  const double a1 = double(w1) / double(h1), a2 = double(w2) / double(h2);
  return !(std::abs(a1 - a2) <= 0.01 * std::min(a1, a2));
}

std::string presentFile(const std::vector<std::string>& candidates) {
  namespace fs = std::filesystem;
  for (const std::string& path : candidates) {
    std::error_code ec;
    if (fs::exists(fs::symlink_status(path, ec))) return path;
  }
  return "";
}

ColorImage resizeColorArea(const ColorImage& color, int width, int height) {
  if (color.width() == width && color.height() == height) return color;
  if (color.empty() || width <= 0 || height <= 0) throw Error("cannot resize an empty colour image");
  const std::vector<Tap> tx = areaTaps(color.width(), width), ty = areaTaps(color.height(), height);
  // Rows first (to the output width), then columns, in float.
  std::vector<float> rows(size_t(width) * size_t(color.height()) * 3);
  for (int y = 0; y < color.height(); ++y)
    for (int x = 0; x < width; ++x) {
      float acc[3] = {0, 0, 0};
      const Tap& t = tx[size_t(x)];
      for (size_t k = 0; k < t.weights.size(); ++k) {
        const Rgb8 p = color(t.first + int(k), y);
        acc[0] += t.weights[k] * p.r, acc[1] += t.weights[k] * p.g, acc[2] += t.weights[k] * p.b;
      }
      std::copy(acc, acc + 3, &rows[(size_t(y) * width + x) * 3]);
    }
  ColorImage out(width, height);
  for (int y = 0; y < height; ++y)
    for (int x = 0; x < width; ++x) {
      float acc[3] = {0, 0, 0};
      const Tap& t = ty[size_t(y)];
      for (size_t k = 0; k < t.weights.size(); ++k)
        for (int c = 0; c < 3; ++c) acc[c] += t.weights[k] * rows[(size_t(t.first + int(k)) * width + x) * 3 + c];
      auto byte = [](float v) { return uint8_t(std::clamp(std::lround(v), 0L, 255L)); };
      out(x, y) = {byte(acc[0]), byte(acc[1]), byte(acc[2]), 255};
    }
  return out;
}

FrameListSource::FrameListSource(FrameList list) : list_(std::move(list)) {
  if (list_.frames.empty()) throw Error(list_.folder + ": no frames found (" + list_.layout + " layout)");
  if (!(list_.depth_units_per_metre > 0 && std::isfinite(list_.depth_units_per_metre)))
    throw Error(list_.folder + ": depth scale must be a positive number of units per metre, got " +
                std::to_string(list_.depth_units_per_metre));
  if (!(list_.fx > 0 && list_.fy > 0)) throw Error(list_.folder + ": no positive focal length (" +
                                                   list_.intrinsics_source + ")");
  for (const FrameFiles& f : list_.frames) {
    requireFrameFile(f.depth, "depth image");
    if (!f.color.empty()) requireFrameFile(f.color, "colour image");
  }
  const std::string& first = list_.frames.front().depth;
  const DepthImage depth = readDepthPng(first, list_.depth_units_per_metre);
  if (list_.expected_width > 0 &&
      (depth.width() != list_.expected_width || depth.height() != list_.expected_height))
    throw Error("depth image " + first + " is " + std::to_string(depth.width()) + "x" +
                std::to_string(depth.height()) + " but " + list_.intrinsics_source + " describes " +
                std::to_string(list_.expected_width) + "x" + std::to_string(list_.expected_height));
  intrinsics_ = {list_.fx, list_.fy, list_.cx, list_.cy, depth.width(), depth.height()};
  const std::string problem = cameraProblem(intrinsics_);
  if (!problem.empty())
    throw Error(list_.intrinsics_source + ": " + problem + " (the depth images, e.g. " + first + ", are " +
                std::to_string(depth.width()) + "x" + std::to_string(depth.height()) + ")");
}

RgbdFrame FrameListSource::load(int index) const {
  if (index < 0 || index >= size())
    throw Error(list_.folder + ": frame " + std::to_string(index) + " out of range (" + std::to_string(size()) +
                " frames)");
  const FrameFiles& f = list_.frames[size_t(index)];
  RgbdFrame frame;
  frame.index = index;
  frame.timestamp = f.timestamp;
  frame.name = f.name;
  frame.T_world_cam_given = f.T_world_cam;
  frame.depth = readScaledDepthPng(f.depth, list_.depth_units_per_metre, list_.depth_invalid_value);
  const int w = intrinsics_.width, h = intrinsics_.height;
  if (frame.depth.width() != w || frame.depth.height() != h)
    throw Error("depth image " + f.depth + " is " + std::to_string(frame.depth.width()) + "x" +
                std::to_string(frame.depth.height()) + ", the sequence is " + std::to_string(w) + "x" +
                std::to_string(h));
  if (!f.color.empty()) {
    frame.color = readColorImage(f.color);
    if (frame.color.width() != w || frame.color.height() != h) {
      const std::string sizes = "colour image " + f.color + " is " + std::to_string(frame.color.width()) + "x" +
                                std::to_string(frame.color.height()) + " but its depth image " + f.depth + " is " +
                                std::to_string(w) + "x" + std::to_string(h);
      if (!list_.resize_color) throw Error(sizes);
      if (aspectRatiosDiffer(frame.color.width(), frame.color.height(), w, h))
        throw Error(sizes + ": another aspect ratio, so resizing the colour onto the depth would stretch it");
      frame.color = resizeColorArea(frame.color, w, h);
    }
  }
  return frame;
}

std::string FrameListSource::description() const {
  char scale[64];
  std::snprintf(scale, sizeof scale, "%g", double(list_.depth_units_per_metre));
  int posed = 0;
  for (const FrameFiles& f : list_.frames) posed += f.T_world_cam ? 1 : 0;
  std::string d = list_.layout + " " + list_.folder + ": " + std::to_string(size()) + " frames " +
                  std::to_string(intrinsics_.width) + "x" + std::to_string(intrinsics_.height) +
                  ", intrinsics from " + list_.intrinsics_source + ", depth " + scale + " units/m (" +
                  list_.depth_scale_source + ")";
  if (posed) d += ", " + std::to_string(posed) + " poses";
  if (!list_.color_registered) d += ", colour not registered to depth";
  return d;
}

Trajectory FrameListSource::groundTruth() const {
  Trajectory out;
  for (const FrameFiles& f : list_.frames)
    if (f.T_world_cam) out.push_back({f.timestamp, *f.T_world_cam});
  return out;
}

}  // namespace vf
