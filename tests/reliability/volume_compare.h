#pragma once
// Helpers of the reliability tests: fusing TUM frames and comparing volumes voxel for voxel.
#include <algorithm>
#include <cstring>
#include <numeric>
#include <string>
#include <tuple>
#include <vector>

#include "brick_lookup.h"
#include "fusion/pipeline.h"

namespace vf::test {

// Index (in `a`) of the first brick that `b` lacks or whose voxels (TSDF, weight, colour, class
// vote) differ; -1 when both hold the same bricks with the same voxels. Bricks are matched by
// coordinate: where a brick sits in the pool depends on the order threads reached it.
inline long firstDifferentBrick(const BrickVolumeView& a, const BrickVolumeView& b) {
  if (a.brick_count != b.brick_count) return long(std::min(a.brick_count, b.brick_count));
  const BrickLookup lookup(b);
  for (size_t n = 0; n < a.brick_count; ++n) {
    const Vec3i c = a.coords[n];
    const int64_t j = lookup.find(c.x * kBrickSize, c.y * kBrickSize, c.z * kBrickSize);
    if (j < 0) return long(n);
    const size_t first = n * kBrickVoxels;
    if (std::memcmp(a.tsdf + first, b.tsdf + j, kBrickVoxels * sizeof(TsdfVoxel)) != 0 ||
        std::memcmp(a.color + first, b.color + j, kBrickVoxels * sizeof(Rgb8)) != 0)
      return long(n);
    if (a.class_vote && std::memcmp(a.class_vote + first, b.class_vote + j, kBrickVoxels * 4) != 0) return long(n);
  }
  return -1;
}

inline bool sameBits(const Pose& a, const Pose& b) {
  return std::memcmp(a.matrix().data(), b.matrix().data(), sizeof(double) * 16) == 0;
}

// The default voxel (5.86 mm) and depth range: what reconstruct fuses the shared captures with.
inline PipelineParams teddyParams(float voxel_size_m = 3.0f / 512.0f) {
  PipelineParams params;
  params.volume.voxel_size_m = voxel_size_m;
  return params;
}

// FNV-1a over every brick's coordinate and voxels in coordinate order: equal hashes = unchanged volume.
inline uint64_t volumeHash(const BrickVolumeView& v) {
  std::vector<size_t> order(v.brick_count);
  std::iota(order.begin(), order.end(), size_t(0));
  std::sort(order.begin(), order.end(), [&](size_t i, size_t j) {
    return std::tie(v.coords[i].x, v.coords[i].y, v.coords[i].z) < std::tie(v.coords[j].x, v.coords[j].y, v.coords[j].z);
  });
  uint64_t h = 1469598103934665603ull;
  auto mix = [&h](const void* p, size_t n) {
    const auto* b = static_cast<const uint8_t*>(p);
    for (size_t i = 0; i < n; ++i) h = (h ^ b[i]) * 1099511628211ull;
  };
  for (size_t n : order) {
    mix(&v.coords[n], sizeof(Vec3i));
    mix(v.tsdf + n * kBrickVoxels, kBrickVoxels * sizeof(TsdfVoxel));
    mix(v.color + n * kBrickVoxels, kBrickVoxels * sizeof(Rgb8));
  }
  return h;
}

}  // namespace vf::test
