#include "viewer/level_frame.h"

#include <algorithm>
#include <cmath>
#include <limits>

namespace vf::viewer {

double floorHeight(std::vector<float> heights) {
  if (heights.empty()) return 0;
  const size_t k = heights.size() / 100;
  std::nth_element(heights.begin(), heights.begin() + k, heights.end());
  const double low = heights[k];
  constexpr double kLayer = 0.02, kBelow = 0.10, kAbove = 0.30;
  const int layers = int(std::lround((kBelow + kAbove) / kLayer));
  std::vector<size_t> count(size_t(layers), 0);
  for (float h : heights) {
    const double at = (h - (low - kBelow)) / kLayer;
    if (at >= 0 && at < layers) ++count[size_t(at)];
  }
  const int densest = int(std::max_element(count.begin(), count.end()) - count.begin());
  // The median over the densest layer and its neighbours: a floor straddling a layer boundary
  // counts whole, and the few vertices of things standing on it do not pull it up.
  const double lo = low - kBelow + (densest - 1) * kLayer, hi = low - kBelow + (densest + 2) * kLayer;
  std::vector<float> layer;
  for (float h : heights)
    if (h >= lo && h < hi) layer.push_back(h);
  if (layer.empty()) return low;
  std::nth_element(layer.begin(), layer.begin() + layer.size() / 2, layer.end());
  return layer[layer.size() / 2];
}

LevelFrame levelFrame(Vec3f up, Vec3f forward, const std::vector<const TriangleMesh*>& surface) {
  LevelFrame f;
  f.up = normalized(up);
  f.forward = normalized(forward - f.up * dot(forward, f.up));  // exactly horizontal
  f.right = cross(f.forward, f.up);
  const float inf = std::numeric_limits<float>::infinity();
  Vec3f lo{inf, inf, inf}, hi{-inf, -inf, -inf};
  std::vector<float> heights;
  for (const TriangleMesh* mesh : surface)
    for (const Vec3f& p : mesh->positions) {
      const Vec3f q = f.toFrame(p);
      lo = {std::min(lo.x, q.x), std::min(lo.y, q.y), std::min(lo.z, q.z)};
      hi = {std::max(hi.x, q.x), std::max(hi.y, q.y), std::max(hi.z, q.z)};
      heights.push_back(q.z);
    }
  if (heights.empty()) return f;
  f.min = lo;
  f.max = hi;
  f.floor_m = floorHeight(std::move(heights));
  return f;
}

PresetView presetView(const LevelFrame& f, CameraPreset preset) {
  switch (preset) {
    case CameraPreset::kTop:
      return {-f.up, f.forward};
    case CameraPreset::kSide:
      return {f.right, f.up};
    default:
      return {f.forward, f.up};
  }
}

}  // namespace vf::viewer
