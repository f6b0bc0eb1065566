#pragma once
// The sparse fusion volume as the kernels see it: a pool of 8x8x8 bricks (slot-major arrays)
// found through a spatial hash of brick coordinates (fusion/brick_hash.h). Bricks are allocated
// where a depth sample's truncation band reaches, so memory and per-frame work follow the
// observed surface, not a box. Coordinates and layout: core/brick_volume.h.
#include <cstddef>
#include <cstdint>

#include "core/brick_volume.h"
#include "core/math.h"
#include "fusion/brick_hash.h"

namespace vf {

// Plain view of the volume's arrays, host or device pointers; passed by value into kernels.
struct VolumeView {
  TsdfVoxel* tsdf = nullptr;       // per slot, kBrickVoxels each
  Rgb8* color = nullptr;           // running average colour (a counts colour observations)
  uint32_t* class_vote = nullptr;  // packed class vote; null when semantic fusion is off
  Vec3i* brick_coords = nullptr;   // per slot: the brick's coordinate
  BrickHashView hash;
  float voxel_size_m = 0;
  float truncation_m = 0;
  // Lookups treat bricks whose last marking stamp (BrickEntry::stamp) is older than this as
  // never allocated: tracking's raycast sees only what recent frames saw. 0: every brick.
  uint32_t min_stamp = 0;

  VF_HD static int64_t voxelIndex(int slot, int local) { return int64_t(slot) * kBrickVoxels + local; }
  // Pool slot of brick b, or -1 where it was never allocated (or is older than min_stamp).
  VF_HD int slotOf(Vec3i b) const {
    if (!brickCoordInRange(b)) return -1;
    const int e = hash.find(brickKey(b));
    if (e < 0) return -1;
    const BrickEntry& entry = hash.entries[e];
    return entry.stamp < min_stamp ? -1 : entry.slot;
  }
  // Index of voxel (x, y, z) in the voxel arrays, or -1 where its brick was never allocated.
  VF_HD int64_t findVoxel(int x, int y, int z) const {
    const int slot = slotOf(brickOfVoxel(x, y, z));
    return slot < 0 ? -1 : voxelIndex(slot, localVoxelIndex(x, y, z));
  }
  // Coordinate of the first voxel of the brick in `slot`.
  VF_HD Vec3i brickOrigin(int slot) const {
    const Vec3i b = brick_coords[slot];
    return {b.x * kBrickSize, b.y * kBrickSize, b.z * kBrickSize};
  }
  // World position of voxel (x, y, z)'s sample (cell centre).
  VF_HD Vec3f voxelCenter(int x, int y, int z) const {
    return {(x + 0.5f) * voxel_size_m, (y + 0.5f) * voxel_size_m, (z + 0.5f) * voxel_size_m};
  }
  // Continuous voxel coordinate of a world point, such that integer values are voxel centres.
  VF_HD Vec3f toVoxel(Vec3f p_world) const {
    const float inv = 1.f / voxel_size_m;
    return {p_world.x * inv - 0.5f, p_world.y * inv - 0.5f, p_world.z * inv - 0.5f};
  }
};

}  // namespace vf
