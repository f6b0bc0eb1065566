#pragma once
// Surface reconstruction (KinectFusion section 3.3): projective TSDF update with a weight cap,
// restricted to the bricks that the current depth can reach.
#include <cstring>

#include "core/image.h"
#include "core/intrinsics.h"
#include "fusion/atomics.h"
#include "fusion/fast_math.h"
#include "fusion/volume.h"

namespace vf {

// The depth readings that are fused, and so the only ones that mark bricks: within
// [min_depth_m, max_depth_m] (false for NaN). MarkBricksKernel and IntegrateKernel must agree.
VF_HD bool fusedDepthReading(float d, float min_depth_m, float max_depth_m) {
  return d >= min_depth_m && d <= max_depth_m;
}

// Allocates (on first touch) and lists every brick that holds a voxel the integration can fuse
// within the truncation band. A work item covers a block of stride_px x stride_px pixels: the
// voxel centres that project into the block (its pixels' cells, [x0 - 0.5, x1 - 0.5) in u) at a
// camera depth within a band [d - trunc, d + trunc] of one of its pixels fill a frustum segment,
// which is cut along the depth into pieces of step_vox voxels; the bricks holding a voxel centre
// inside a piece's bounding box (the hull of its eight corners) are touched. Only the boxes'
// corners reach beyond the band: on tests/fusion's room corner 83 % of the listed bricks hold a
// band voxel. Depth outside [min_depth_m, max_depth_m] is neither marked nor fused. Testing each
// box brick against the piece's six planes as well (2026-12-04) listed only 2-4 % fewer bricks
// on fr1/xyz, teddy and the kitchen, and the tests cost more marking time than they saved.
//
// Voxels in free space in front of the band are fused too (towards +1) but only inside listed
// bricks, as before: a brick that no piece's box reaches is neither allocated nor walked. The
// earlier marking, a cube of half a step plus 1.5 pixels around each step of the block's first
// pixel, listed 20 % of its bricks for nothing and allocated 14-19 % of its bricks for voxels
// that no frame ever fused; and it missed the band of a pixel whose block neighbour lay across
// a depth edge.
struct MarkBricksKernel {
  ImageView<const float> depth;
  Intrinsics intrinsics;
  Rigid3f T_world_cam;
  VolumeView volume;
  float min_depth_m = 0.2f, max_depth_m = 4.f;
  uint32_t stamp = 1;      // this frame (1-based): an entry stamped with it is already listed
  int* frame_entries;      // hash entries touched by this frame, each once
  int* frame_count;
  int* overflow;           // set when the hash table is too full for an insert
  // A brick last listed by a frame stamped before this one (not 0: never) starts afresh: its
  // voxels are cleared before this frame fuses into it (IcpParams::restart_stale_bricks).
  uint32_t restart_before = 0;
  int* restarted = nullptr;  // counts the bricks restarted
  int stride_px = 2;
  // Piece length. Half as long listed 0.8 % fewer bricks on the synthetic room, for a third more
  // marking time (9.1 against 6.8 % of the run).
  float step_vox = 4.f;
  // Pixel blocks per work item, a square tile_px on a side. Neighbouring blocks reach the same
  // bricks over and over (at 1 m a brick covers ~150 blocks); a tile remembers the bricks it
  // touched last, and only the others go to the hash table. The CPU takes 16 x 16 blocks per
  // item; CUDA, which wants many threads, one.
  int tile_px = 1;
  // A band is a few pieces deep; the cap only guards against absurd parameters. Past it the
  // pieces grow longer, so the cover stays whole.
  static constexpr int kMaxPieces = 256;
  // The remembered bricks, direct-mapped by the low bits of each coordinate, so that bricks
  // within a block of 8 x 8 x 8 (a CPU tile's reach; CUDA: 2 x 2 x 2, one block's band, 64
  // bytes a thread) never evict each other. The room scan went from 8 hash touches per
  // brick a frame to 1.9 (a 32-entry table of mixed coordinates before; tiles of 8 x 8).
#ifdef __CUDA_ARCH__
  static constexpr int kRecentShift = 1;
#else
  static constexpr int kRecentShift = 3;
#endif
  static constexpr int kRecentMask = (1 << kRecentShift) - 1;
  static constexpr int kRecentBricks = 1 << (3 * kRecentShift);
  static constexpr int kStepLanes = 8;
  // Slack for float rounding between this kernel's geometry and the integration's projection of
  // each voxel: a hundredth of a pixel across, a hundredth of a voxel in the boxes, a twentieth
  // of a voxel in depth. It only ever adds bricks.
  static constexpr float kSlackPx = 0.01f, kSlackVox = 0.01f, kSlackDepthVox = 0.05f;

  VF_HD int columns() const { return (depth.width + stride_px - 1) / stride_px; }
  VF_HD int rows() const { return (depth.height + stride_px - 1) / stride_px; }
  VF_HD int tilesX() const { return (columns() + tile_px - 1) / tile_px; }
  VF_HD int itemCount() const { return tilesX() * ((rows() + tile_px - 1) / tile_px); }

  VF_HD void operator()(int item) const {
    uint64_t recent[kRecentBricks];
    for (int k = 0; k < kRecentBricks; ++k) recent[k] = kEmptyBrickKey;
    const Rays rays = worldRays();
    const int c0 = (item % tilesX()) * tile_px, r0 = (item / tilesX()) * tile_px;
    for (int r = r0; r < r0 + tile_px && r < rows(); ++r)
      for (int c = c0; c < c0 + tile_px && c < columns(); ++c) markBlock(rays, c * stride_px, r * stride_px, recent);
  }

  // The ray through pixel (u, v) at camera depth 1, in world axes and voxel units, is affine in
  // u and v: at + u * per_u + v * per_v. So its bounds over a block of pixels are, per axis, the
  // sum of the bounds of each term, with no ray computed per corner.
  struct Rays {
    Vec3f at, per_u, per_v;
  };
  VF_HD Rays worldRays() const {
    const float inv_voxel = 1.f / volume.voxel_size_m;
    const Vec3f per_u = T_world_cam.rotate(Vec3f{1.f / intrinsics.fx, 0.f, 0.f}) * inv_voxel;
    const Vec3f per_v = T_world_cam.rotate(Vec3f{0.f, 1.f / intrinsics.fy, 0.f}) * inv_voxel;
    const Vec3f at = T_world_cam.rotate(intrinsics.backProject(0.f, 0.f, 1.f)) * inv_voxel;
    return {at, per_u, per_v};
  }

  VF_HD bool validDepth(float d) const { return fusedDepthReading(d, min_depth_m, max_depth_m); }

  VF_HD void markBlock(const Rays& rays, int x0, int y0, uint64_t* recent) const {
    const int x1 = x0 + stride_px < depth.width ? x0 + stride_px : depth.width;
    const int y1 = y0 + stride_px < depth.height ? y0 + stride_px : depth.height;
    float d_lo = 3.0e38f, d_hi = -3.0e38f;
    for (int y = y0; y < y1; ++y)
      for (int x = x0; x < x1; ++x) {
        const float d = depth(x, y);
        if (validDepth(d)) d_lo = minFloat(d_lo, d), d_hi = maxFloat(d_hi, d);
      }
    if (d_lo > d_hi) return;  // no valid depth in the block
    const float trunc = volume.truncation_m;
    // Bands that overlap are one band; across a depth edge each pixel keeps its own, and the
    // gap between them (free space or unseen) is not listed.
    if (d_hi - d_lo <= 2.f * trunc) {
      markBand(rays, x0, y0, x1, y1, d_lo - trunc, d_hi + trunc, recent);
      return;
    }
    for (int y = y0; y < y1; ++y)
      for (int x = x0; x < x1; ++x) {
        const float d = depth(x, y);
        if (validDepth(d)) markBand(rays, x0, y0, x1, y1, d - trunc, d + trunc, recent);
      }
  }

  // The bricks holding a voxel centre that projects into pixels [x0, x1) x [y0, y1) at a camera
  // depth in [z_begin, z_end].
  VF_HD void markBand(const Rays& rays, int x0, int y0, int x1, int y1, float z_begin, float z_end,
                      uint64_t* recent) const {
    const float inv_voxel = 1.f / volume.voxel_size_m;
    const float slack_z = kSlackDepthVox * volume.voxel_size_m;
    z_begin = maxFloat(z_begin - slack_z, 0.5f * min_depth_m);  // > 0: the bounds scale by depth
    z_end += slack_z;
    // The block's rays, in voxels per metre of camera depth, bound per world axis: at depth z
    // every voxel coordinate of the block lies within origin + z * [lo, hi].
    const float u0 = float(x0) - 0.5f - kSlackPx, u1 = float(x1) - 0.5f + kSlackPx;
    const float v0 = float(y0) - 0.5f - kSlackPx, v1 = float(y1) - 0.5f + kSlackPx;
    const Vec3f a = rays.per_u * u0, b = rays.per_u * u1, c = rays.per_v * v0, d = rays.per_v * v1;
    const Vec3f lo{rays.at.x + minFloat(a.x, b.x) + minFloat(c.x, d.x), rays.at.y + minFloat(a.y, b.y) + minFloat(c.y, d.y),
                   rays.at.z + minFloat(a.z, b.z) + minFloat(c.z, d.z)};
    const Vec3f hi{rays.at.x + maxFloat(a.x, b.x) + maxFloat(c.x, d.x), rays.at.y + maxFloat(a.y, b.y) + maxFloat(c.y, d.y),
                   rays.at.z + maxFloat(a.z, b.z) + maxFloat(c.z, d.z)};
    const Vec3f origin = volume.toVoxel(T_world_cam.t);
    // Pieces of about step_vox voxels along the block's central ray.
    const Vec3f ray_mid = intrinsics.backProject(0.5f * float(x0 + x1 - 1), 0.5f * float(y0 + y1 - 1), 1.f);
    const float span = (z_end - z_begin) * norm(ray_mid) * inv_voxel / step_vox;
    const int pieces = span < float(kMaxPieces) ? int(span) + 1 : kMaxPieces;
    const float dz = (z_end - z_begin) / float(pieces);
    Vec3i last_lo{0, 0, 0}, last_hi{-1, -1, -1};  // the bricks the previous piece touched (none yet)
    // The pieces' brick boxes kStepLanes at a time, in a loop of their own so that the CPU
    // compiler computes them in vector lanes; the touches follow one piece at a time.
    for (int s0 = 0; s0 < pieces; s0 += kStepLanes) {
      int box[6][kStepLanes];  // lo x, y, z, hi x, y, z (bricks); lo > hi: no voxel centre inside
      VF_SIMD_LOOP
      for (int j = 0; j < kStepLanes; ++j) {
        const float za = z_begin + float(s0 + j) * dz;
        const float zb = s0 + j + 1 >= pieces ? z_end : z_begin + float(s0 + j + 1) * dz;
        // Lowest and highest voxel coordinate of the piece per axis (za < zb, both > 0).
        const float lx = origin.x + (lo.x >= 0.f ? za : zb) * lo.x - kSlackVox;
        const float ly = origin.y + (lo.y >= 0.f ? za : zb) * lo.y - kSlackVox;
        const float lz = origin.z + (lo.z >= 0.f ? za : zb) * lo.z - kSlackVox;
        const float hx = origin.x + (hi.x >= 0.f ? zb : za) * hi.x + kSlackVox;
        const float hy = origin.y + (hi.y >= 0.f ? zb : za) * hi.y + kSlackVox;
        const float hz = origin.z + (hi.z >= 0.f ? zb : za) * hi.z + kSlackVox;
        box[0][j] = int(ceilf(lx)) >> kBrickShift;
        box[1][j] = int(ceilf(ly)) >> kBrickShift;
        box[2][j] = int(ceilf(lz)) >> kBrickShift;
        box[3][j] = int(floorf(hx)) >> kBrickShift;
        box[4][j] = int(floorf(hy)) >> kBrickShift;
        box[5][j] = int(floorf(hz)) >> kBrickShift;
      }
      for (int j = 0; j < kStepLanes && s0 + j < pieces; ++j) {
        const Vec3i b_lo{box[0][j], box[1][j], box[2][j]}, b_hi{box[3][j], box[4][j], box[5][j]};
        // Pieces are shorter than a brick: most cover the same bricks as the piece before.
        if (b_lo.x == last_lo.x && b_lo.y == last_lo.y && b_lo.z == last_lo.z && b_hi.x == last_hi.x &&
            b_hi.y == last_hi.y && b_hi.z == last_hi.z)
          continue;
        last_lo = b_lo, last_hi = b_hi;
        touchBox(b_lo, b_hi, recent);
      }
    }
  }

  VF_HD void touchBox(Vec3i lo, Vec3i hi, uint64_t* recent) const {
    for (int bz = lo.z; bz <= hi.z; ++bz)
      for (int by = lo.y; by <= hi.y; ++by)
        for (int bx = lo.x; bx <= hi.x; ++bx) {
          // Touching a brick twice changes nothing, so forgetting one (a collision) is harmless.
          const Vec3i b{bx, by, bz};
          const uint64_t key = brickKey(b);
          const int way = (bx & kRecentMask) | (by & kRecentMask) << kRecentShift | (bz & kRecentMask) << (2 * kRecentShift);
          uint64_t& remembered = recent[way];
          if (remembered == key) continue;
          remembered = key;
          touch(b);
        }
  }

  VF_HD void touch(Vec3i brick) const {
    if (!brickCoordInRange(brick)) return;
    const int e = volume.hash.insert(brickKey(brick));
    if (e < 0) {
      *overflow = 1;
      return;
    }
    // The exchange tells exactly one thread that the entry is new to this frame: it is listed once.
    uint32_t* entry_stamp = &volume.hash.entries[e].stamp;
    if (loadRelaxed(entry_stamp) == stamp) return;
    const uint32_t previous = exchange(entry_stamp, stamp);
    if (previous == stamp) return;
    frame_entries[atomicIncrement(frame_count)] = e;
    if (previous != 0 && previous < restart_before) restart(volume.hash.entries[e].slot);
  }

  // Clears a brick's voxels (the state of a brick never fused). Such a brick was listed before,
  // so it has its slot (or none, where the pool was full then); no other thread touches it
  // while the frame is marked, and integration comes after.
  VF_HD void restart(int slot) const {
    if (slot < 0) return;
    const int64_t first = VolumeView::voxelIndex(slot, 0);
    for (int k = 0; k < kBrickVoxels; ++k) {
      volume.tsdf[first + k] = TsdfVoxel{0, 0};
      volume.color[first + k] = Rgb8{0, 0, 0, 0};
      if (volume.class_vote) volume.class_vote[first + k] = 0u;
    }
    atomicIncrement(restarted);
  }
};

// Counts the touched entries that have no pool slot yet (the host grows the pool to fit).
struct CountNewBricksKernel {
  BrickHashView hash;
  const int* frame_entries;
  int* count;
  VF_HD void operator()(int i) const {
    if (hash.entries[frame_entries[i]].slot < 0) atomicIncrement(count);
  }
};

// Gives every touched entry without a slot the next free slot of the pool, and lists the slot of
// every touched brick for integration. A brick the full pool cannot take stays without a slot
// (-1): it is neither integrated nor seen by the raycast, and *pool_full tells the host.
struct AssignSlotsKernel {
  VolumeView volume;
  const int* frame_entries;
  int* frame_slots;
  int* slot_count;  // slots in use; may run past the capacity by the bricks that did not fit
  int pool_capacity;
  int* pool_full;

  VF_HD void operator()(int i) const {
    const int e = frame_entries[i];
    int slot = volume.hash.entries[e].slot;
    if (slot < 0) {
      slot = atomicIncrement(slot_count);
      if (slot >= pool_capacity) {
        *pool_full = 1;
        slot = -1;
      } else {
        volume.hash.entries[e].slot = slot;
        volume.brick_coords[slot] = brickFromKey(volume.hash.entries[e].key);
      }
    }
    frame_slots[i] = slot;
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
  const int* slots;  // the bricks this frame touched (AssignSlotsKernel); -1 = not in the pool
  int slot_count = 0;  // entries of slots
  ImageView<const float> depth;
  ImageView<const Rgb8> color;        // data may be null; the depth's size or a larger image of the same view
  float color_scale_x = 1.f, color_scale_y = 1.f;  // colour pixels per depth pixel
  ImageView<const uint16_t> labels;   // data may be null
  ImageView<const uint8_t> static_mask;  // data may be null; 0 = dynamic pixel: vote, do not fuse
  Intrinsics intrinsics;
  Rigid3f T_cam_world;
  float min_depth_m = 0.2f, max_depth_m = 4.f;  // as MarkBricksKernel: other readings are not fused
  int max_weight = 128;
  uint32_t max_class_confidence = 255;
  bool probabilistic_vote = false;  // IntegrationParams::class_vote
  uint32_t vote_seed = 0;
  uint32_t stamp = 0;               // the frame's brick stamp (1-based), hashed by the vote

  // Work item: one row of 8 voxels along x inside a marked brick (64 rows per brick). The row's
  // camera-space points are stepped incrementally instead of transformed one by one.
  static constexpr int kRowsPerBrick = kBrickSize * kBrickSize;

  VF_HD void operator()(int row_item) const {
    const int brick = row_item / kRowsPerBrick;
    const int row = row_item % kRowsPerBrick;  // (z & 7) * 8 + (y & 7)
#ifndef __CUDA_ARCH__
    // The CPU walks the listed bricks in order, but they lie anywhere in the pool, and most rows
    // touch their colours only here and there, too sparse for the hardware prefetcher: this row
    // of the next brick is fetched now, a brick's time (~1 us) before it is needed.
    if (brick + 1 < slot_count && slots[brick + 1] >= 0) {
      const int64_t ahead = VolumeView::voxelIndex(slots[brick + 1], row * kBrickSize);
      __builtin_prefetch(volume.tsdf + ahead, 1);
      if (color.data) __builtin_prefetch(volume.color + ahead, 1);
    }
#endif
    const int slot = slots[brick];
    if (slot < 0) return;
    const Vec3i origin = volume.brickOrigin(slot);
    const Vec3i first = {origin.x, origin.y + (row & kBrickMask), origin.z + (row >> kBrickShift)};
    const Vec3f p0 = T_cam_world * volume.voxelCenter(first.x, first.y, first.z);
    const Vec3f step = T_cam_world.rotate(Vec3f{volume.voxel_size_m, 0.f, 0.f});
    // The probabilistic vote hashes a voxel's identity: its brick key and place in the brick,
    // the same whichever slot the brick got, so every backend and every run agree.
    const uint64_t voxel_id_base = brickKey(volume.brick_coords[slot]) << (3 * kBrickShift);
    const int64_t first_index = VolumeView::voxelIndex(slot, row * kBrickSize);
    // The row's projections first, in a loop of their own so that the CPU compiler does all
    // eight divisions at once; a lane with z <= 0 is refused by updateVoxel before its
    // (meaningless) u, v are read.
    float u[kBrickSize], v[kBrickSize], z[kBrickSize];
    for (int k = 0; k < kBrickSize; ++k) {
      const Vec3f p = p0 + step * float(k);
      z[k] = p.z;
      intrinsics.projectAnyDepth(p, u[k], v[k]);
    }
    if (labels.data) {
      for (int k = 0; k < kBrickSize; ++k)
        updateVoxel(first_index + k, voxel_id_base | uint64_t(row * kBrickSize + k), u[k], v[k], z[k]);
    } else {
      fuseRow(first_index, u, v, z);
    }
  }

  // updateVoxel for a whole row of a frame without labels, written without branches so that
  // the CPU compiler runs the eight voxels in vector lanes: every lane computes its update and
  // the lanes that must not change store their old value (a row belongs to one work item, so
  // rewriting an unchanged voxel is harmless). The same operations per voxel as updateVoxel,
  // so both give the same bits.
  VF_HD void fuseRow(int64_t first_index, const float u[kBrickSize], const float v[kBrickSize],
                     const float z[kBrickSize]) const {
    // Everything per lane is 32 bits wide (masks as int, a voxel and a colour as one word), so
    // that one vector holds the row; conditions combine with & rather than && (no branch per
    // lane). The image reads get loops of their own: the compiler does not gather for this
    // target, but vectorises the arithmetic around them.
    const float trunc = volume.truncation_m;
    float uk[kBrickSize], vk[kBrickSize], d[kBrickSize], sdf[kBrickSize];
    int in_image[kBrickSize], pixel[kBrickSize], fuse[kBrickSize], near_surface[kBrickSize];
    for (int k = 0; k < kBrickSize; ++k) {
      in_image[k] = (z[k] > 0.f) & (u[k] >= -0.5f) & (v[k] >= -0.5f) & (u[k] < float(depth.width) - 0.5f) &
                    (v[k] < float(depth.height) - 0.5f);
      uk[k] = in_image[k] ? u[k] : 0.f;  // finite where refused, so the pixel below is in the image
      vk[k] = in_image[k] ? v[k] : 0.f;
      pixel[k] = int(floorf(vk[k] + 0.5f)) * depth.width + int(floorf(uk[k] + 0.5f));
    }
    for (int k = 0; k < kBrickSize; ++k) d[k] = depth[pixel[k]];
    for (int k = 0; k < kBrickSize; ++k) {
      // fusedDepthReading, with & for the vector lanes.
      const int valid = in_image[k] & (d[k] >= min_depth_m) & (d[k] <= max_depth_m);
      sdf[k] = valid ? d[k] - z[k] : trunc;
      fuse[k] = valid & !(sdf[k] < -trunc);  // behind the surface: unobserved
      near_surface[k] = fuse[k] & (sdf[k] < trunc);
    }
    // A third of the rows (behind the surface) fuse nothing; their voxels are left untouched in
    // memory, as are the colours of rows without a voxel near the surface.
    int any_fused = 0, any_near = 0;
    for (int k = 0; k < kBrickSize; ++k) any_fused |= fuse[k], any_near |= near_surface[k];
    if (!any_fused) return;
    static_assert(sizeof(TsdfVoxel) == 4 && sizeof(Rgb8) == 4, "a voxel and a colour are one word each");
    TsdfVoxel* voxels = volume.tsdf + first_index;
    for (int k = 0; k < kBrickSize; ++k) {
      int32_t word;  // tsdf in the low half, weight in the high half (little-endian)
      memcpy(&word, voxels + k, 4);
      const int old_weight = int(uint32_t(word) >> 16);
      const float tsdf = sdf[k] < trunc ? sdf[k] / trunc : 1.f;
      const float w = float(old_weight);
      const int old_tsdf = int32_t(uint32_t(word) << 16) >> 16;  // sign-extends the low half
      const float fused = (float(old_tsdf) * w + tsdf * kTsdfScale) / (w + 1.f);
      const int new_tsdf = int(clampFloat(rintf(fused), -kTsdfScale, kTsdfScale));
      const int new_weight = old_weight < max_weight ? old_weight + 1 : old_weight;
      const int32_t fused_word = int32_t((uint32_t(new_tsdf) & 0xFFFFu) | uint32_t(new_weight) << 16);
      word = fuse[k] ? fused_word : word;
      memcpy(voxels + k, &word, 4);
    }
    if (!color.data || !any_near) return;
    int32_t in[kBrickSize];
    for (int k = 0; k < kBrickSize; ++k) pixel[k] = colorPixel(uk[k], vk[k]);
    for (int k = 0; k < kBrickSize; ++k) memcpy(in + k, color.data + pixel[k], 4);
    Rgb8* colors = volume.color + first_index;
    for (int k = 0; k < kBrickSize; ++k) {
      int32_t old;  // r, g, b, a from the low byte up
      memcpy(&old, colors + k, 4);
      const int count = int(uint32_t(old) >> 24);
      const float cw = float(count);
      const float inv = 1.f / (cw + 1.f);
      const int r = int(rintf((float(old & 0xFF) * cw + float(in[k] & 0xFF)) * inv));
      const int g = int(rintf((float((old >> 8) & 0xFF) * cw + float((in[k] >> 8) & 0xFF)) * inv));
      const int b = int(rintf((float((old >> 16) & 0xFF) * cw + float((in[k] >> 16) & 0xFF)) * inv));
      const int a = count < 254 ? count + 1 : count;
      const int32_t blended = int32_t(uint32_t(r) | uint32_t(g) << 8 | uint32_t(b) << 16 | uint32_t(a) << 24);
      const int32_t word = near_surface[k] ? blended : old;
      memcpy(colors + k, &word, 4);
    }
  }

  // The colour pixel that depth position (u, v) (>= -0.5) falls in; the depth pixel itself when
  // the images have one size.
  VF_HD int colorPixel(float u, float v) const {
    const int x = clampInt(int((u + 0.5f) * color_scale_x), 0, color.width - 1);
    const int y = clampInt(int((v + 0.5f) * color_scale_y), 0, color.height - 1);
    return y * color.width + x;
  }

  // Eq. (11)-(12) for one voxel whose centre lies at depth z and projects to (u, v).
  VF_HD void updateVoxel(int64_t index, uint64_t voxel_id, float u, float v, float z) const {
    if (z <= 0.f) return;
    // Compared as floats first: a voxel just in front of the camera projects far outside.
    if (!(u >= -0.5f && v >= -0.5f && u < float(depth.width) - 0.5f && v < float(depth.height) - 0.5f)) return;
    const int px = int(floorf(u + 0.5f)), py = int(floorf(v + 0.5f));
    const float d = depth(px, py);
    if (!fusedDepthReading(d, min_depth_m, max_depth_m)) return;
    const float sdf = d - z;
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
        const Rgb8 in = color[colorPixel(u, v)];
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
                                            probabilistic_vote, vote_seed, voxel_id, stamp);
  }
};

}  // namespace vf
