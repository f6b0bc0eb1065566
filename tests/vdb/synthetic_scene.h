#pragma once
// Sparse volumes filled directly with analytic signed distances, as fusion would leave them:
// weights only within the truncation band, two classes on the two halves (x below / above
// split_x_m) with distinct colours. Bricks are allocated as voxels are written.
#include <algorithm>
#include <cmath>
#include <functional>
#include <map>
#include <tuple>

#include "core/brick_volume.h"

namespace vf::test {

constexpr int kClassLeft = 1, kClassRight = 2;
constexpr Rgb8 kColorLeft{200, 40, 30, 255}, kColorRight{30, 180, 60, 255};

// A box of voxels to fill: box voxel (x, y, z) is global voxel origin_vox + (x, y, z).
struct SyntheticSpec {
  Vec3i dims{64, 64, 64};
  float voxel_size_m = 0.01f;
  float truncation_m = 0.04f;
  Vec3i origin_vox{-32, -32, -32};
};

class SyntheticVolume {
 public:
  SyntheticVolume(const SyntheticSpec& spec, bool with_classes) : spec_(spec) {
    bricks_.voxel_size_m = spec.voxel_size_m;
    bricks_.truncation_m = spec.truncation_m;
    bricks_.with_classes = with_classes;
  }
  const SyntheticSpec& spec() const { return spec_; }
  Vec3i global(int x, int y, int z) const { return {spec_.origin_vox.x + x, spec_.origin_vox.y + y, spec_.origin_vox.z + z}; }
  Vec3f voxelCenter(int x, int y, int z) const {
    const Vec3i g = global(x, y, z);
    return {(g.x + 0.5f) * spec_.voxel_size_m, (g.y + 0.5f) * spec_.voxel_size_m, (g.z + 0.5f) * spec_.voxel_size_m};
  }
  // Index of box voxel (x, y, z) in the brick arrays, allocating its brick on first use.
  size_t voxel(int x, int y, int z) {
    const Vec3i g = global(x, y, z);
    const Vec3i b = brickOfVoxel(g.x, g.y, g.z);
    auto [it, inserted] = index_.try_emplace({b.x, b.y, b.z}, bricks_.coords.size());
    if (inserted) {
      bricks_.coords.push_back(b);
      bricks_.tsdf.resize(bricks_.tsdf.size() + kBrickVoxels, TsdfVoxel{0, 0});
      bricks_.color.resize(bricks_.color.size() + kBrickVoxels, Rgb8{0, 0, 0, 0});
      if (bricks_.with_classes) bricks_.class_vote.resize(bricks_.class_vote.size() + kBrickVoxels, 0u);
    }
    return it->second * kBrickVoxels + size_t(localVoxelIndex(g.x, g.y, g.z));
  }
  HostBrickVolume& bricks() { return bricks_; }
  BrickVolumeView view() const { return bricks_.view(); }

 private:
  SyntheticSpec spec_;
  HostBrickVolume bricks_;
  std::map<std::tuple<int, int, int>, size_t> index_;
};

// sdf(p) in metres; every voxel with |sdf| < truncation gets `weight`.
inline void fillSdf(SyntheticVolume& volume, const std::function<float(Vec3f)>& sdf, float split_x_m,
                    uint16_t weight = 10) {
  const SyntheticSpec& s = volume.spec();
  HostBrickVolume& v = volume.bricks();
  for (int z = 0; z < s.dims.z; ++z)
    for (int y = 0; y < s.dims.y; ++y)
      for (int x = 0; x < s.dims.x; ++x) {
        const Vec3f p = volume.voxelCenter(x, y, z);
        const float d = sdf(p);
        if (std::fabs(d) >= s.truncation_m) continue;
        const size_t i = volume.voxel(x, y, z);
        const float prev_w = v.tsdf[i].weight;
        // Union of shapes: keep the nearer surface where two overlap.
        if (prev_w > 0 && std::fabs(v.tsdf[i].tsdf * (s.truncation_m / kTsdfScale)) <= std::fabs(d)) continue;
        v.tsdf[i].tsdf = int16_t(std::lround(std::clamp(d / s.truncation_m, -1.f, 1.f) * kTsdfScale));
        v.tsdf[i].weight = weight;
        const bool left = p.x < split_x_m;
        v.color[i] = left ? kColorLeft : kColorRight;
        if (v.with_classes) v.class_vote[i] = packClassVote(left ? kClassLeft : kClassRight, 7);
      }
}

// A 64^3 box of 1 cm voxels (or `dims` of `voxel_m`) centred on the world origin.
inline SyntheticSpec sphereSpec(int dims = 64, float voxel_m = 0.01f) {
  SyntheticSpec spec;
  spec.dims = {dims, dims, dims};
  spec.voxel_size_m = voxel_m;
  spec.truncation_m = 4 * voxel_m;
  spec.origin_vox = {-dims / 2, -dims / 2, -dims / 2};
  return spec;
}

inline std::function<float(Vec3f)> sphereSdf(Vec3f c, float r) {
  return [=](Vec3f p) { return norm(p - c) - r; };
}

}  // namespace vf::test
