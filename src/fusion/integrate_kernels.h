#pragma once
// Surface reconstruction (KinectFusion section 3.3): projective TSDF update with a weight cap,
// restricted to the bricks that the current depth can reach.
#include "core/image.h"
#include "core/intrinsics.h"
#include "fusion/atomics.h"
#include "fusion/fast_math.h"
#include "fusion/volume.h"

namespace vf {

// Marks every brick within the truncation band of a depth sample with the frame's stamp.
// The band [d - trunc, d + trunc] along each (strided) pixel ray is walked in steps of
// step_vox voxels; each step marks the bricks overlapping a box that covers the step and the
// footprint of the skipped neighbouring pixels, so no voxel the update would touch is missed.
struct MarkBricksKernel {
  ImageView<const float> depth;
  Intrinsics intrinsics;
  Rigid3f T_world_cam;
  VolumeView volume;
  uint32_t stamp = 1;
  int* allocated_list;   // every brick ever touched, appended on first touch
  int* allocated_count;
  int stride_px = 2;
  float step_vox = 2.f;

  VF_HD void operator()(int i) const {
    const int cols = (depth.width + stride_px - 1) / stride_px;
    const int x = (i % cols) * stride_px, y = (i / cols) * stride_px;
    if (y >= depth.height) return;
    const float d = depth(x, y);
    if (d <= 0.f) return;
    const float trunc = volume.truncation_m;
    const Vec3f ray_cam = intrinsics.backProject(float(x), float(y), 1.f);  // z = 1
    const float inv_voxel = 1.f / volume.voxel_size_m;
    // Half-size of the box around each step, in voxels: half a step, the strided pixels'
    // footprint at the far end of the band, and one voxel for the projection's rounding.
    const float footprint_vox = (d + trunc) * float(stride_px) / intrinsics.fx * inv_voxel;
    const float half_box = 0.5f * step_vox + footprint_vox + 1.f;
    const float z_begin = d - trunc > 0.f ? d - trunc : 0.f, z_end = d + trunc;
    const float dz = step_vox * volume.voxel_size_m / norm(ray_cam);
    for (float z = z_begin; z <= z_end + 0.5f * dz; z += dz) {
      const Vec3f p = volume.toVoxel(T_world_cam * (ray_cam * z));
      const int bx0 = clampInt(int(floorf((p.x - half_box) * 0.125f)), 0, volume.bricks.x - 1);
      const int bx1 = clampInt(int(floorf((p.x + half_box) * 0.125f)), -1, volume.bricks.x - 1);
      const int by0 = clampInt(int(floorf((p.y - half_box) * 0.125f)), 0, volume.bricks.y - 1);
      const int by1 = clampInt(int(floorf((p.y + half_box) * 0.125f)), -1, volume.bricks.y - 1);
      const int bz0 = clampInt(int(floorf((p.z - half_box) * 0.125f)), 0, volume.bricks.z - 1);
      const int bz1 = clampInt(int(floorf((p.z + half_box) * 0.125f)), -1, volume.bricks.z - 1);
      for (int bz = bz0; bz <= bz1; ++bz)
        for (int by = by0; by <= by1; ++by)
          for (int bx = bx0; bx <= bx1; ++bx) {
            const int brick = volume.brickIndex(bx, by, bz);
            uint32_t* s = volume.brick_stamp + brick;
            // The exchange tells exactly one thread that the brick is new: it is listed once.
            if (loadRelaxed(s) != stamp && exchange(s, stamp) == 0)
              allocated_list[atomicIncrement(allocated_count)] = brick;
          }
    }
  }
};

// Appends the index of every brick carrying this frame's stamp to a list.
struct CollectBricksKernel {
  const uint32_t* brick_stamp;
  uint32_t stamp;
  int* count;
  int* list;

  VF_HD void operator()(int b) const {
    if (brick_stamp[b] == stamp) list[atomicIncrement(count)] = b;
  }
};

// Streaming majority vote (Boyer-Moore): the stored class keeps its place while it is seen at
// least as often as all others together; confidence counts the surplus. Deterministic and
// order-independent enough for fusion, 4 bytes per voxel.
// probabilistic: the seed's rule instead. A differing label replaces the stored class (confidence
// 1) with probability 1/(conf+1), else the vote is kept unchanged; an agreeing label adds 1. The
// random number is a hash of (seed, voxel index, frame stamp), so it is reproducible and the
// same on every backend; integer-only so CPU and CUDA agree bit for bit.
VF_HD uint32_t voteUpdate(uint32_t vote, uint32_t label, uint32_t max_confidence, bool probabilistic = false,
                          uint32_t seed = 0, uint64_t voxel = 0, uint32_t stamp = 0) {
  uint32_t cls = voteClass(vote), conf = voteConfidence(vote);
  if (conf == 0) return packClassVote(label, 1);
  if (cls == label) return packClassVote(cls, conf < max_confidence ? conf + 1 : conf);
  if (!probabilistic) return packClassVote(cls, conf - 1);
  // splitmix64 finaliser over the three inputs.
  uint64_t h = (uint64_t(seed) << 32 | stamp) ^ (voxel * 0x9E3779B97F4A7C15ull);
  h = (h ^ (h >> 30)) * 0xBF58476D1CE4E5B9ull;
  h = (h ^ (h >> 27)) * 0x94D049BB133111EBull;
  h ^= h >> 31;
  // u uniform in [0, 2^32): replace when u < 2^32 / (conf + 1).
  const uint64_t u = h >> 32;
  return u * (uint64_t(conf) + 1) < (uint64_t(1) << 32) ? packClassVote(label, 1) : vote;
}

// One voxel of a marked brick: project, compare with the measured depth, update the running
// averages of eq. (11)-(12) with unit weight per frame, capped at max_weight.
struct IntegrateKernel {
  VolumeView volume;
  const int* bricks;
  ImageView<const float> depth;
  ImageView<const Rgb8> color;        // data may be null
  ImageView<const uint16_t> labels;   // data may be null
  ImageView<const uint8_t> static_mask;  // data may be null; 0 = dynamic pixel: vote, do not fuse
  Intrinsics intrinsics;
  Rigid3f T_cam_world;
  int max_weight = 128;
  uint32_t max_class_confidence = 255;
  bool probabilistic_vote = false;  // IntegrationParams::class_vote
  uint32_t vote_seed = 0;
  uint32_t stamp = 0;               // the frame's brick stamp (1-based), hashed by the vote

  // Work item: one row of 8 voxels along x inside a marked brick (64 rows per brick). The row's
  // camera-space points are stepped incrementally instead of transformed one by one.
  static constexpr int kRowsPerBrick = kBrickSize * kBrickSize;

  VF_HD void operator()(int row_item) const {
    const int brick = bricks[row_item / kRowsPerBrick];
    const int row = row_item % kRowsPerBrick;  // (z & 7) * 8 + (y & 7)
    const size_t first = size_t(brick) * kBrickVoxels + size_t(row) * kBrickSize;
    const Vec3i c = volume.voxelCoord(first);
    const Vec3f p0 = T_cam_world * volume.voxelCenter(c.x, c.y, c.z);
    const Vec3f step = T_cam_world.rotate(Vec3f{volume.voxel_size_m, 0.f, 0.f});
    for (int k = 0; k < kBrickSize; ++k) updateVoxel(first + size_t(k), p0 + step * float(k));
  }

  // Eq. (11)-(12) for one voxel whose centre is p in camera coordinates.
  VF_HD void updateVoxel(size_t index, Vec3f p) const {
    if (p.z <= 0.f) return;
    float u, v;
    intrinsics.project(p, u, v);
    const int px = int(floorf(u + 0.5f)), py = int(floorf(v + 0.5f));
    if (!depth.inside(px, py)) return;
    const float d = depth(px, py);
    if (d <= 0.f) return;
    const float sdf = d - p.z;
    const float trunc = volume.truncation_m;
    if (sdf < -trunc) return;  // behind the surface: unobserved
    const int pixel = py * depth.width + px;
    const uint16_t label = labels.data ? labels[pixel] : uint16_t(0xFFFF);
    const bool fuse_geometry = !static_mask.data || static_mask[pixel] != 0;
    const bool near_surface = sdf < trunc;
    if (fuse_geometry) {
      const float tsdf = sdf < trunc ? sdf / trunc : 1.f;
      TsdfVoxel& vox = volume.tsdf[index];
      const float w = float(vox.weight);
      const float fused = (float(vox.tsdf) * w + tsdf * kTsdfScale) / (w + 1.f);
      vox.tsdf = int16_t(clampFloat(rintf(fused), -kTsdfScale, kTsdfScale));
      if (vox.weight < max_weight) vox.weight = uint16_t(vox.weight + 1);
      if (color.data && near_surface) {
        Rgb8& rgb = volume.color[index];
        const Rgb8 in = color[pixel];
        // The alpha byte counts color observations so color averages only over frames that
        // actually saw the voxel near the surface.
        const float cw = float(rgb.a);
        const float inv = 1.f / (cw + 1.f);
        rgb.r = uint8_t(rintf((float(rgb.r) * cw + float(in.r)) * inv));
        rgb.g = uint8_t(rintf((float(rgb.g) * cw + float(in.g)) * inv));
        rgb.b = uint8_t(rintf((float(rgb.b) * cw + float(in.b)) * inv));
        if (rgb.a < 254) rgb.a = uint8_t(rgb.a + 1);
      }
    }
    if (labels.data && volume.class_vote && near_surface && label != 0xFFFF)
      volume.class_vote[index] = voteUpdate(volume.class_vote[index], label, max_class_confidence,
                                            probabilistic_vote, vote_seed, index, stamp);
  }
};

}  // namespace vf
