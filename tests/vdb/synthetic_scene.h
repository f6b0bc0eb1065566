#pragma once
// Dense volumes filled directly with analytic signed distances, as fusion would leave them:
// weights only within the truncation band, stamps on the touched bricks, two classes on the two
// halves (x below / above the centre) with distinct colors.
#include <algorithm>
#include <cmath>
#include <functional>

#include "core/volume_spec.h"
#include "fusion/dense_volume.h"

namespace vf::test {

constexpr int kClassLeft = 1, kClassRight = 2;
constexpr Rgb8 kColorLeft{200, 40, 30, 255}, kColorRight{30, 180, 60, 255};

// sdf(p) in metres; every voxel with |sdf| < truncation gets `weight`.
inline void fillSdf(DenseVolume& volume, const std::function<float(Vec3f)>& sdf, float split_x_m,
                    uint16_t weight = 10) {
  const VolumeView& v = volume.view();
  for (int z = 0; z < v.dims.z; ++z)
    for (int y = 0; y < v.dims.y; ++y)
      for (int x = 0; x < v.dims.x; ++x) {
        const Vec3f p = v.voxelCenter(x, y, z);
        const float d = sdf(p);
        if (std::fabs(d) >= v.truncation_m) continue;
        const size_t i = v.voxelIndex(x, y, z);
        const float prev_w = v.tsdf[i].weight;
        // Union of shapes: keep the nearer surface where two overlap.
        if (prev_w > 0 && std::fabs(v.sdfMetres(i)) <= std::fabs(d)) continue;
        v.tsdf[i].tsdf = int16_t(std::lround(std::clamp(d / v.truncation_m, -1.f, 1.f) * kTsdfScale));
        v.tsdf[i].weight = weight;
        const bool left = p.x < split_x_m;
        v.color[i] = left ? kColorLeft : kColorRight;
        if (v.class_vote) v.class_vote[i] = packClassVote(left ? kClassLeft : kClassRight, 7);
        v.brick_stamp[v.brickIndex(x >> 3, y >> 3, z >> 3)] = 1;
      }
}

inline VolumeSpec sphereSpec(int dims = 64, float voxel_m = 0.01f) {
  VolumeSpec spec;
  spec.dims = {dims, dims, dims};
  spec.voxel_size_m = voxel_m;
  spec.truncation_m = 4 * voxel_m;
  spec.origin_m = {-0.5f * dims * voxel_m, -0.5f * dims * voxel_m, -0.5f * dims * voxel_m};
  return spec;
}

inline std::function<float(Vec3f)> sphereSdf(Vec3f c, float r) {
  return [=](Vec3f p) { return norm(p - c) - r; };
}

}  // namespace vf::test
