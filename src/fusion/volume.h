#pragma once
// The dense fusion volume: what every stage reads and writes, and what src/vdb converts.
//
// Memory is laid out in 8x8x8 bricks (brick-major, then z, y, x inside a brick) so that a
// trilinear sample touches one or two cache lines and a brick that no depth sample ever reached
// is never written: its pages stay untouched (the host allocation is lazily committed), which is
// what keeps a 512^3 volume's resident memory proportional to the observed surface.
#include <cstddef>
#include <cstdint>

#include "core/math.h"
#include "core/volume_spec.h"

namespace vf {

constexpr int kBrickSize = VolumeSpec::kBrickSize;
constexpr int kBrickVoxels = kBrickSize * kBrickSize * kBrickSize;

// TSDF values are stored as int16, normalised by the truncation: sdf_m = tsdf / kTsdfScale * trunc.
constexpr float kTsdfScale = 32767.0f;

// Class vote packed in 32 bits (semantic fusion): low 16 bits class id, high 16 bits confidence.
constexpr uint32_t kUnknownClass = 0xFFFFu;
VF_HD uint32_t packClassVote(uint32_t class_id, uint32_t confidence) {
  return (confidence << 16) | (class_id & 0xFFFFu);
}
VF_HD uint32_t voteClass(uint32_t vote) { return vote & 0xFFFFu; }
VF_HD uint32_t voteConfidence(uint32_t vote) { return vote >> 16; }

// TSDF and weight side by side (KinectFusion's short2): the raycast and the integration read
// both for every sample, so one 4-byte load serves both.
struct TsdfVoxel {
  int16_t tsdf;     // normalised signed distance (see kTsdfScale), meaningful where weight > 0
  uint16_t weight;  // number of fused observations (capped), 0 = never seen
};

// Plain view of the volume's arrays, host or device pointers; passed by value into kernels.
struct VolumeView {
  TsdfVoxel* tsdf = nullptr;      // tsdf + weight per voxel
  Rgb8* color = nullptr;          // running average color (a unused)
  uint32_t* class_vote = nullptr; // packed class vote; null when semantic fusion is off
  uint32_t* brick_stamp = nullptr;  // per brick: last frame (1-based) that touched it, 0 = never
  Vec3i dims{0, 0, 0};            // voxels
  Vec3i bricks{0, 0, 0};          // dims / kBrickSize
  float voxel_size_m = 0;
  float truncation_m = 0;
  Vec3f origin_m{0, 0, 0};

  VF_HD int brickIndex(int bx, int by, int bz) const { return (bz * bricks.y + by) * bricks.x + bx; }
  VF_HD size_t voxelIndex(int x, int y, int z) const {
    const size_t brick = size_t(brickIndex(x >> 3, y >> 3, z >> 3));
    return brick * kBrickVoxels + size_t(((z & 7) << 6) | ((y & 7) << 3) | (x & 7));
  }
  // Inverse of voxelIndex.
  VF_HD Vec3i voxelCoord(size_t index) const {
    const int brick = int(index / kBrickVoxels);
    const int local = int(index % kBrickVoxels);
    const int bx = brick % bricks.x, by = (brick / bricks.x) % bricks.y, bz = brick / (bricks.x * bricks.y);
    return {bx * 8 + (local & 7), by * 8 + ((local >> 3) & 7), bz * 8 + (local >> 6)};
  }
  VF_HD bool contains(int x, int y, int z) const {
    return x >= 0 && y >= 0 && z >= 0 && x < dims.x && y < dims.y && z < dims.z;
  }
  VF_HD int brickCount() const { return bricks.x * bricks.y * bricks.z; }
  // World position of voxel (x, y, z)'s sample (cell centre).
  VF_HD Vec3f voxelCenter(int x, int y, int z) const {
    return {origin_m.x + (x + 0.5f) * voxel_size_m, origin_m.y + (y + 0.5f) * voxel_size_m,
            origin_m.z + (z + 0.5f) * voxel_size_m};
  }
  // Continuous voxel coordinate of a world point, such that integer values are voxel centres.
  VF_HD Vec3f toVoxel(Vec3f p_world) const {
    const float inv = 1.f / voxel_size_m;
    return {(p_world.x - origin_m.x) * inv - 0.5f, (p_world.y - origin_m.y) * inv - 0.5f,
            (p_world.z - origin_m.z) * inv - 0.5f};
  }
  VF_HD float sdfMetres(size_t index) const { return tsdf[index].tsdf * (truncation_m / kTsdfScale); }
  VF_HD uint16_t weightAt(size_t index) const { return tsdf[index].weight; }
};

}  // namespace vf
