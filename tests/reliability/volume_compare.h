#pragma once
// Helpers of the reliability tests: fusing TUM frames and comparing volumes voxel for voxel.
#include <cstring>
#include <string>

#include "fusion/dense_volume.h"
#include "fusion/pipeline.h"

namespace vf::test {

// Index of the first brick whose stamp or voxels (TSDF, weight, colour, class vote) differ
// between two volumes of the same spec, -1 when they are identical. Every brick is compared,
// observed or not.
inline int firstDifferentBrick(const DenseVolume& a, const DenseVolume& b) {
  const VolumeView& va = a.view();
  const VolumeView& vb = b.view();
  for (int brick = 0; brick < va.brickCount(); ++brick) {
    if (va.brick_stamp[brick] != vb.brick_stamp[brick]) return brick;
    if (va.brick_stamp[brick] == 0) continue;  // never touched: zero pages on both sides
    const size_t first = size_t(brick) * kBrickVoxels;
    if (std::memcmp(va.tsdf + first, vb.tsdf + first, kBrickVoxels * sizeof(TsdfVoxel)) != 0 ||
        std::memcmp(va.color + first, vb.color + first, kBrickVoxels * sizeof(Rgb8)) != 0)
      return brick;
    if (va.class_vote && std::memcmp(va.class_vote + first, vb.class_vote + first, kBrickVoxels * 4) != 0)
      return brick;
  }
  return -1;
}

inline bool sameBits(const Pose& a, const Pose& b) {
  return std::memcmp(a.matrix().data(), b.matrix().data(), sizeof(double) * 16) == 0;
}

// A small volume that holds the fr3 teddy scene (KinectFusion placement: x, y centred, z ahead).
inline PipelineParams teddyParams(int voxels = 128) {
  PipelineParams params;
  params.volume.dims = {voxels, voxels, voxels};
  params.volume.voxel_size_m = 3.0f / float(voxels);
  return params;
}

}  // namespace vf::test

namespace vf::test {

// FNV-1a over every observed brick's index, stamp and voxels: equal hashes = unchanged volume.
inline uint64_t volumeHash(const DenseVolume& volume) {
  const VolumeView& v = volume.view();
  uint64_t h = 1469598103934665603ull;
  auto mix = [&h](const void* p, size_t n) {
    const auto* b = static_cast<const uint8_t*>(p);
    for (size_t i = 0; i < n; ++i) h = (h ^ b[i]) * 1099511628211ull;
  };
  for (int brick : volume.observedBricks()) {
    const size_t first = size_t(brick) * kBrickVoxels;
    mix(&brick, sizeof brick);
    mix(&v.brick_stamp[brick], sizeof(uint32_t));
    mix(v.tsdf + first, kBrickVoxels * sizeof(TsdfVoxel));
    mix(v.color + first, kBrickVoxels * sizeof(Rgb8));
  }
  return h;
}

}  // namespace vf::test
