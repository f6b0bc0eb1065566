#pragma once
// The fused volume as plain data: 8x8x8 voxel bricks at integer brick coordinates, with no box
// around them. Fusion keeps them in a brick pool behind a spatial hash (src/fusion); src/vdb
// turns them into OpenVDB leaves (one brick = one leaf); checkpoints store them. Nothing here
// knows a backend.
//
// Voxel (i, j, k), integers of any sign, covers the cube [i, i+1) x [j, j+1) x [k, k+1) voxel
// edges from the world origin; its sample sits at the cube's centre ((i + 0.5) * voxel_size_m, ...).
// It lives in brick (i >> 3, j >> 3, k >> 3) at local index ((k & 7) << 6) | ((j & 7) << 3) | (i & 7).
#include <cstddef>
#include <cstdint>
#include <vector>

#include "core/math.h"

namespace vf {

constexpr int kBrickShift = 3;                       // voxel coordinate >> kBrickShift = brick coordinate
constexpr int kBrickSize = 1 << kBrickShift;         // voxels along a brick edge
constexpr int kBrickMask = kBrickSize - 1;           // voxel coordinate & kBrickMask = position in its brick
constexpr int kBrickVoxels = kBrickSize * kBrickSize * kBrickSize;

VF_HD Vec3i brickOfVoxel(int x, int y, int z) { return {x >> kBrickShift, y >> kBrickShift, z >> kBrickShift}; }
VF_HD int localVoxelIndex(int x, int y, int z) {
  return ((z & kBrickMask) << (2 * kBrickShift)) | ((y & kBrickMask) << kBrickShift) | (x & kBrickMask);
}
// Inverse of localVoxelIndex: the voxel's offset inside its brick.
VF_HD Vec3i localVoxelOffset(int local) {
  return {local & kBrickMask, (local >> kBrickShift) & kBrickMask, local >> (2 * kBrickShift)};
}

// TSDF values are stored as int16, normalised by the truncation: sdf_m = tsdf / kTsdfScale * trunc.
constexpr float kTsdfScale = 32767.0f;

// TSDF and weight side by side (KinectFusion's short2): the raycast and the integration read
// both for every sample, so one 4-byte load serves both. Measured against (2026-12-04): the
// TSDF as a 2-byte code with a value for "never observed" and the weight in an array of its
// own, so that the raycast reads only the codes, twice as many per cache line. Raycast -6 to
// -12 % (fr1/xyz, the kitchen, the room), but integration +3 to +10 %: a fused row then touches
// a line of each array, and the rows that fuse nothing no longer spare whole lines. The whole
// run gained nothing, so the word stayed.
struct TsdfVoxel {
  int16_t tsdf;     // normalised signed distance (see kTsdfScale), meaningful where weight > 0
  uint16_t weight;  // number of fused observations (capped), 0 = never seen
};

// Class vote packed in 32 bits (semantic fusion): low 16 bits class id, high 16 bits confidence.
constexpr uint32_t kUnknownClass = 0xFFFFu;
VF_HD uint32_t packClassVote(uint32_t class_id, uint32_t confidence) {
  return (confidence << 16) | (class_id & 0xFFFFu);
}
VF_HD uint32_t voteClass(uint32_t vote) { return vote & 0xFFFFu; }
VF_HD uint32_t voteConfidence(uint32_t vote) { return vote >> 16; }

// Read-only view of bricks in host memory: brick n has coordinate coords[n] and its voxels at
// [n * kBrickVoxels, (n + 1) * kBrickVoxels) of each array.
struct BrickVolumeView {
  float voxel_size_m = 0;
  float truncation_m = 0;
  size_t brick_count = 0;
  const Vec3i* coords = nullptr;
  const TsdfVoxel* tsdf = nullptr;
  const Rgb8* color = nullptr;          // running average colour (a counts colour observations)
  const uint32_t* class_vote = nullptr; // null when fused without classes

  bool hasClasses() const { return class_vote != nullptr; }
  float sdfMetres(size_t voxel) const { return tsdf[voxel].tsdf * (truncation_m / kTsdfScale); }
};

// Bricks owned in host memory (a download from the GPU, a checkpoint being restored).
struct HostBrickVolume {
  float voxel_size_m = 0;
  float truncation_m = 0;
  bool with_classes = false;
  std::vector<Vec3i> coords;
  std::vector<TsdfVoxel> tsdf;
  std::vector<Rgb8> color;
  std::vector<uint32_t> class_vote;

  void resize(size_t bricks) {
    coords.resize(bricks);
    tsdf.resize(bricks * kBrickVoxels);
    color.resize(bricks * kBrickVoxels);
    class_vote.resize(with_classes ? bricks * kBrickVoxels : 0);
  }
  // A copy of bricks held elsewhere (a pipeline's live volume, valid only until its next frame).
  static HostBrickVolume copyOf(const BrickVolumeView& v) {
    HostBrickVolume h;
    h.voxel_size_m = v.voxel_size_m;
    h.truncation_m = v.truncation_m;
    h.with_classes = v.hasClasses();
    const size_t voxels = v.brick_count * kBrickVoxels;
    h.coords.assign(v.coords, v.coords + v.brick_count);
    h.tsdf.assign(v.tsdf, v.tsdf + voxels);
    h.color.assign(v.color, v.color + voxels);
    if (h.with_classes) h.class_vote.assign(v.class_vote, v.class_vote + voxels);
    return h;
  }
  BrickVolumeView view() const {
    return {voxel_size_m, truncation_m, coords.size(), coords.data(), tsdf.data(), color.data(),
            with_classes ? class_vote.data() : nullptr};
  }
};

}  // namespace vf
