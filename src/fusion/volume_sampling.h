#pragma once
// Reading the TSDF volume at continuous positions: trilinear interpolation that refuses to mix
// in never-observed voxels (their zero would fake a surface), and the gradient for normals.
#include "fusion/fast_math.h"
#include "fusion/volume.h"

namespace vf {

// Reads the 8 voxels around g. Returns false when a corner was never observed (unallocated brick
// or weight 0: its zero would fake a surface). f receives the fractional position in the cell.
VF_HD bool cellCorners(const VolumeView& volume, Vec3f g, float corners[8], Vec3f& f) {
  const float fx0 = floorf(g.x), fy0 = floorf(g.y), fz0 = floorf(g.z);
  if (!(fabsf(fx0) < 1.0e9f && fabsf(fy0) < 1.0e9f && fabsf(fz0) < 1.0e9f)) return false;  // NaN, far away
  const int x = int(fx0), y = int(fy0), z = int(fz0);
  f = {g.x - fx0, g.y - fy0, g.z - fz0};
  TsdfVoxel c[8];
  if ((x & kBrickMask) != kBrickMask && (y & kBrickMask) != kBrickMask && (z & kBrickMask) != kBrickMask) {
    // All eight corners in one brick: one lookup, fixed offsets from the first.
    const int64_t first = volume.findVoxel(x, y, z);
    if (first < 0) return false;
    const TsdfVoxel* base = volume.tsdf + first;
    c[0] = base[0], c[1] = base[1], c[2] = base[8], c[3] = base[9];
    c[4] = base[64], c[5] = base[65], c[6] = base[72], c[7] = base[73];
  } else {
    // The cell straddles brick faces (a third of all cells): each brick it reaches is looked up
    // once, usually two, not once per corner. Brick b of the 2x2x2 the cell can reach has bit
    // 0, 1, 2 set for the next brick along x, y, z.
    const int next[3] = {(x & kBrickMask) == kBrickMask, (y & kBrickMask) == kBrickMask, (z & kBrickMask) == kBrickMask};
    int slots[8];
    for (int b = 0; b < 8; ++b) {
      const int dx = b & 1, dy = (b >> 1) & 1, dz = b >> 2;
      if ((dx > next[0]) || (dy > next[1]) || (dz > next[2])) continue;  // the cell does not reach it
      slots[b] = volume.slotOf(brickOfVoxel(x + dx, y + dy, z + dz));
      if (slots[b] < 0) return false;
    }
    for (int k = 0; k < 8; ++k) {
      const int dx = k & 1, dy = (k >> 1) & 1, dz = k >> 2;
      const int b = (dx & next[0]) | (dy & next[1]) << 1 | (dz & next[2]) << 2;
      c[k] = volume.tsdf[VolumeView::voxelIndex(slots[b], localVoxelIndex(x + dx, y + dy, z + dz))];
    }
  }
  for (int k = 0; k < 8; ++k) {
    if (c[k].weight == 0) return false;
    corners[k] = float(c[k].tsdf) * (1.f / kTsdfScale);
  }
  return true;
}

// The trilinear value and its analytic gradient (per voxel) from the same 8 corners.
VF_HD bool sampleTsdfGradient(const VolumeView& volume, Vec3f g, float& out, Vec3f& gradient) {
  float c[8];
  Vec3f f;
  if (!cellCorners(volume, g, c, f)) return false;
  const float c00 = c[0] + f.x * (c[1] - c[0]), c10 = c[2] + f.x * (c[3] - c[2]);
  const float c01 = c[4] + f.x * (c[5] - c[4]), c11 = c[6] + f.x * (c[7] - c[6]);
  const float c0 = c00 + f.y * (c10 - c00), c1 = c01 + f.y * (c11 - c01);
  out = c0 + f.z * (c1 - c0);
  const float dx0 = (c[1] - c[0]) + f.y * ((c[3] - c[2]) - (c[1] - c[0]));
  const float dx1 = (c[5] - c[4]) + f.y * ((c[7] - c[6]) - (c[5] - c[4]));
  gradient = {dx0 + f.z * (dx1 - dx0), (c10 - c00) + f.z * ((c11 - c01) - (c10 - c00)), c1 - c0};
  return true;
}

// Trilinear TSDF at continuous voxel coordinate g (integers are voxel centres), normalised to
// [-1, 1]; false where any corner is unobserved.
VF_HD bool sampleTsdf(const VolumeView& volume, Vec3f g, float& out) {
  float value;
  Vec3f unused_gradient;
  if (!sampleTsdfGradient(volume, g, value, unused_gradient)) return false;
  out = value;
  return true;
}

// Index of the voxel nearest to continuous voxel coordinate g, or -1 where its brick was never
// allocated.
VF_HD int64_t nearestVoxel(const VolumeView& volume, Vec3f g) {
  return volume.findVoxel(int(floorf(g.x + 0.5f)), int(floorf(g.y + 0.5f)), int(floorf(g.z + 0.5f)));
}

// Color of the voxel nearest to g, if it has one.
VF_HD bool nearestColor(const VolumeView& volume, Vec3f g, Rgb8& out) {
  const int64_t index = nearestVoxel(volume, g);
  if (index < 0) return false;
  out = volume.color[index];
  return out.a > 0;
}

}  // namespace vf
