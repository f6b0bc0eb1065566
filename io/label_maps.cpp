#include "io/label_maps.h"

#include <cmath>
#include <filesystem>
#include <vector>

#include "core/error.h"
#include "io/image_io.h"

namespace vf {
namespace fs = std::filesystem;

LabelImage resampleLabelsNearest(const LabelImage& labels, int width, int height) {
  if (labels.empty()) throw Error("cannot resample an empty label map");
  if (width <= 0 || height <= 0)
    throw Error("label map target size must be positive, got " + std::to_string(width) + "x" + std::to_string(height));
  if (width == labels.width() && height == labels.height()) return labels;
  // Integer arithmetic: (2x + 1) * in / (2 * out) is floor((x + 0.5) * in / out) exactly, so a
  // ratio like 720/192 = 3.75 never lands on a neighbour through rounding error.
  std::vector<int> src_x(static_cast<size_t>(width)), src_y(static_cast<size_t>(height));
  for (int x = 0; x < width; ++x) src_x[size_t(x)] = int((2LL * x + 1) * labels.width() / (2LL * width));
  for (int y = 0; y < height; ++y) src_y[size_t(y)] = int((2LL * y + 1) * labels.height() / (2LL * height));
  LabelImage out(width, height);
  for (int y = 0; y < height; ++y)
    for (int x = 0; x < width; ++x) out(x, y) = labels(src_x[size_t(x)], src_y[size_t(y)]);
  return out;
}

LabelMapDir::LabelMapDir(const std::string& folder) : folder_(folder) {
  if (!fs::is_directory(folder_)) throw Error("label map folder not found: " + folder_);
}

std::string LabelMapDir::pathFor(const std::string& stem, int index) const {
  const std::string by_stem = (fs::path(folder_) / (stem + ".png")).string();
  if (!stem.empty() && fs::exists(by_stem)) return by_stem;
  const std::string by_index = (fs::path(folder_) / (std::to_string(index) + ".png")).string();
  if (index >= 0 && fs::exists(by_index)) return by_index;
  return stem.empty() ? by_index : by_stem;
}

LabelLookup LabelMapDir::load(const std::string& stem, int index, int target_width, int target_height) const {
  LabelLookup out;
  out.path = pathFor(stem, index);
  if (!fs::exists(out.path)) return out;
  LabelImage labels = readLabelPng(out.path);
  // A different aspect ratio means a rotated or cropped map; stretching it would put classes
  // on the wrong surfaces.
  const double aspect_in = double(labels.width()) / labels.height();
  const double aspect_target = double(target_width) / target_height;
  if (std::abs(aspect_in / aspect_target - 1.0) > 0.02)
    throw Error("label map " + out.path + " is " + std::to_string(labels.width()) + "x" +
                std::to_string(labels.height()) + ", not the aspect ratio of the " + std::to_string(target_width) +
                "x" + std::to_string(target_height) + " depth image (rotated or cropped?)");
  out.labels = resampleLabelsNearest(labels, target_width, target_height);
  return out;
}

}  // namespace vf
