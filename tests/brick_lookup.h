#pragma once
// Voxels of a sparse brick volume by global voxel coordinate, for tests: the bricks of a
// BrickVolumeView indexed by their coordinates.
#include <cstdint>
#include <map>
#include <tuple>

#include "core/brick_volume.h"

namespace vf::test {

class BrickLookup {
 public:
  explicit BrickLookup(const BrickVolumeView& v) : v_(v) {
    for (size_t n = 0; n < v.brick_count; ++n) index_[key(v.coords[n])] = n;
  }
  size_t brickCount() const { return v_.brick_count; }
  bool hasBrick(Vec3i b) const { return index_.count(key(b)) != 0; }
  // Index of voxel (x, y, z) in the view's arrays, or -1 where its brick is absent.
  int64_t find(int x, int y, int z) const {
    const auto it = index_.find(key(brickOfVoxel(x, y, z)));
    return it == index_.end() ? -1 : int64_t(it->second) * kBrickVoxels + localVoxelIndex(x, y, z);
  }
  // The voxel, or an unobserved one (weight 0) where its brick is absent.
  TsdfVoxel tsdf(int x, int y, int z) const {
    const int64_t i = find(x, y, z);
    return i < 0 ? TsdfVoxel{0, 0} : v_.tsdf[i];
  }
  float sdfMetres(int x, int y, int z) const { return tsdf(x, y, z).tsdf * (v_.truncation_m / kTsdfScale); }
  Vec3f voxelCenter(int x, int y, int z) const {
    return {(x + 0.5f) * v_.voxel_size_m, (y + 0.5f) * v_.voxel_size_m, (z + 0.5f) * v_.voxel_size_m};
  }
  const BrickVolumeView& view() const { return v_; }

 private:
  static std::tuple<int, int, int> key(Vec3i b) { return {b.x, b.y, b.z}; }
  BrickVolumeView v_;
  std::map<std::tuple<int, int, int>, size_t> index_;
};

}  // namespace vf::test
