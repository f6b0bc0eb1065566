#pragma once
// Surface prediction (KinectFusion section 3.4): march each pixel's ray through the TSDF until a
// +/- zero crossing, refine it by linear interpolation (eq. 15), take normals from the TSDF
// gradient. Empty space is skipped a whole brick at a time: a brick no frame touched has no
// surface.
#include "core/image.h"
#include "core/intrinsics.h"
#include "fusion/atomics.h"
#include "fusion/volume_sampling.h"

namespace vf {

// Ray ranges (InfiniTAM's "visible block" trick): every allocated brick is projected into a
// coarse image of kRangeTilePx-pixel tiles that records the nearest and farthest camera depth
// any brick covers. A ray then marches only within its tile's range and skips empty space
// wholesale; a tile no brick covers needs no ray at all.
constexpr int kRangeTilePx = 4;
constexpr float kRangeEmpty = 3.0e38f;

struct ClearRangeKernel {
  float* range_min;
  float* range_max;
  VF_HD void operator()(int i) const {
    range_min[i] = kRangeEmpty;
    range_max[i] = 0.f;
  }
};

struct BrickRangeKernel {
  VolumeView volume;
  const int* bricks;
  Intrinsics intrinsics;
  Rigid3f T_cam_world;
  float near_m = 0.1f;
  float* range_min;
  float* range_max;
  int tiles_x = 0, tiles_y = 0;

  VF_HD void operator()(int i) const {
    const int brick = bricks[i];
    const int bx = brick % volume.bricks.x, by = (brick / volume.bricks.x) % volume.bricks.y,
              bz = brick / (volume.bricks.x * volume.bricks.y);
    float z_lo = 3.0e38f, z_hi = 0.f, u_lo = 3.0e38f, u_hi = -3.0e38f, v_lo = 3.0e38f, v_hi = -3.0e38f;
    bool behind = false;
    for (int k = 0; k < 8; ++k) {
      // Brick corners: the outer faces of its edge voxels.
      const float cx = float(bx * 8 + ((k & 1) ? 8 : 0)), cy = float(by * 8 + ((k & 2) ? 8 : 0)),
                  cz = float(bz * 8 + ((k & 4) ? 8 : 0));
      const Vec3f world{volume.origin_m.x + cx * volume.voxel_size_m, volume.origin_m.y + cy * volume.voxel_size_m,
                        volume.origin_m.z + cz * volume.voxel_size_m};
      const Vec3f p = T_cam_world * world;
      z_lo = p.z < z_lo ? p.z : z_lo;
      z_hi = p.z > z_hi ? p.z : z_hi;
      if (p.z < near_m) {
        behind = true;
        continue;
      }
      float u, v;
      intrinsics.project(p, u, v);
      u_lo = u < u_lo ? u : u_lo, u_hi = u > u_hi ? u : u_hi;
      v_lo = v < v_lo ? v : v_lo, v_hi = v > v_hi ? v : v_hi;
    }
    if (z_hi < near_m) return;  // entirely behind the camera
    if (behind) {                // straddles the image plane: may cover any pixel
      u_lo = v_lo = -1.f;
      u_hi = v_hi = 1.0e6f;
      z_lo = near_m;
    }
    const int tx0 = clampInt(int(floorf(u_lo / kRangeTilePx)), 0, tiles_x);
    const int tx1 = clampInt(int(floorf(u_hi / kRangeTilePx)), -1, tiles_x - 1);
    const int ty0 = clampInt(int(floorf(v_lo / kRangeTilePx)), 0, tiles_y);
    const int ty1 = clampInt(int(floorf(v_hi / kRangeTilePx)), -1, tiles_y - 1);
    for (int ty = ty0; ty <= ty1; ++ty)
      for (int tx = tx0; tx <= tx1; ++tx) {
        atomicMinNonNegative(range_min + ty * tiles_x + tx, z_lo);
        atomicMaxNonNegative(range_max + ty * tiles_x + tx, z_hi);
      }
  }
};

struct RaycastKernel {
  VolumeView volume;
  Intrinsics intrinsics;
  Rigid3f T_world_cam;
  float near_m = 0.2f, far_m = 5.f;
  float min_step_vox = 0.8f, step_fraction = 0.8f;
  ImageView<Vec3f> vertex;  // world frame
  ImageView<Vec3f> normal;  // world frame; (0,0,0) marks "no surface"
  ImageView<Rgb8> color;    // data may be null
  const float* range_min = nullptr;  // per tile camera-depth bounds (BrickRangeKernel)
  const float* range_max = nullptr;
  int tiles_x = 0;

  // Ray parameter range [t0, t1] inside the volume's box (voxel coordinates).
  VF_HD bool clipToVolume(Vec3f o, Vec3f d, float& t0, float& t1) const {
    const float lo[3] = {-0.5f, -0.5f, -0.5f};
    const float hi[3] = {volume.dims.x - 0.5f, volume.dims.y - 0.5f, volume.dims.z - 0.5f};
    const float oo[3] = {o.x, o.y, o.z}, dd[3] = {d.x, d.y, d.z};
    for (int a = 0; a < 3; ++a) {
      if (fabsf(dd[a]) < 1e-9f) {
        if (oo[a] < lo[a] || oo[a] > hi[a]) return false;
        continue;
      }
      float ta = (lo[a] - oo[a]) / dd[a], tb = (hi[a] - oo[a]) / dd[a];
      if (ta > tb) { const float tmp = ta; ta = tb; tb = tmp; }
      t0 = ta > t0 ? ta : t0;
      t1 = tb < t1 ? tb : t1;
    }
    return t0 < t1;
  }

  // Ray parameter where the ray leaves brick (bx, by, bz).
  VF_HD static float brickExit(Vec3f o, Vec3f d, int bx, int by, int bz) {
    const float oo[3] = {o.x, o.y, o.z}, dd[3] = {d.x, d.y, d.z};
    const int b[3] = {bx, by, bz};
    float t = 3.0e38f;
    for (int a = 0; a < 3; ++a) {
      if (fabsf(dd[a]) < 1e-9f) continue;
      const float face = dd[a] > 0.f ? b[a] * 8 + 7.5f : b[a] * 8 - 0.5f;
      const float ta = (face - oo[a]) / dd[a];
      t = ta < t ? ta : t;
    }
    return t;
  }

  VF_HD void operator()(int i) const {
    const int x = i % vertex.width, y = i / vertex.width;
    normal[i] = Vec3f{0.f, 0.f, 0.f};
    vertex[i] = Vec3f{0.f, 0.f, 0.f};
    if (color.data) color[i] = Rgb8{0, 0, 0, 0};
    // March in voxel units: o and d in voxel coordinates, t in voxels along a unit voxel ray.
    const Vec3f ray_world = T_world_cam.rotate(normalized(intrinsics.backProject(float(x), float(y), 1.f)));
    const float inv_voxel = 1.f / volume.voxel_size_m;
    const Vec3f o = volume.toVoxel(T_world_cam.t);
    const Vec3f d = ray_world;
    float t = near_m * inv_voxel, t_end = far_m * inv_voxel;
    const int tile = (y / kRangeTilePx) * tiles_x + x / kRangeTilePx;
    const float z_lo = range_min[tile], z_hi = range_max[tile];
    if (z_lo > z_hi) return;  // no allocated brick projects here
    // Depth z along this pixel's ray is t * |ray_cam| with ray_cam = (.., .., 1); one voxel of slack.
    const float z_to_t = norm(intrinsics.backProject(float(x), float(y), 1.f)) * inv_voxel;
    t = fmaxf(t, z_lo * z_to_t - 1.f);
    t_end = fminf(t_end, z_hi * z_to_t + 1.f);
    if (!clipToVolume(o, d, t, t_end)) return;
    const float trunc_vox = volume.truncation_m * inv_voxel;
    const float unobserved_step = fmaxf(min_step_vox, 0.5f * trunc_vox);
    // Coarse march on single nearest-voxel reads (one load each); the trilinear field is only
    // evaluated once a sign change is bracketed.
    float prev_t = 0.f;
    bool have_prev = false;
    int current_brick = -1;
    bool current_allocated = false;
    while (t < t_end) {
      const Vec3f g = o + d * t;
      const int ix = int(floorf(g.x + 0.5f)), iy = int(floorf(g.y + 0.5f)), iz = int(floorf(g.z + 0.5f));
      if (!volume.contains(ix, iy, iz)) {
        t += min_step_vox;
        have_prev = false;
        continue;
      }
      const int bx = ix >> 3, by = iy >> 3, bz = iz >> 3;
      const int brick = volume.brickIndex(bx, by, bz);
      if (brick != current_brick) {  // look a brick up once, not at every step inside it
        current_brick = brick;
        current_allocated = volume.brick_stamp[brick] != 0;
      }
      if (!current_allocated) {
        // Never advance less than a regular step: a ray grazing a brick face would otherwise
        // creep along it in tiny increments.
        const float t_exit = brickExit(o, d, bx, by, bz);
        t = t_exit > t + min_step_vox ? t_exit + 0.01f : t + min_step_vox;
        have_prev = false;
        continue;
      }
      const TsdfVoxel v = volume.tsdf[volume.voxelIndex(ix, iy, iz)];
      if (v.weight == 0) {
        // Unobserved: no surface within half a truncation band can start here unseen, since
        // every fused surface is preceded by a full band of positive voxels.
        t += unobserved_step;
        have_prev = false;
        continue;
      }
      const float sdf = float(v.tsdf) * (trunc_vox / kTsdfScale);  // voxels
      if (sdf <= 0.f) {
        if (!have_prev) {  // entered behind a surface (or a back face): keep looking
          t += min_step_vox;
          continue;
        }
        if (refineCrossing(o, d, prev_t, t + 1.f, i)) return;
        have_prev = false;  // no trilinear crossing here after all: move on
        t += min_step_vox;
        continue;
      }
      prev_t = t;
      have_prev = true;
      const float step = sdf * step_fraction;
      t += step > min_step_vox ? step : min_step_vox;
    }
  }

  // The crossing between t_a (in front) and t_b (behind), both from coarse nearest-voxel reads.
  // Usually the trilinear field brackets it too and two secant steps (eq. 15) land on it;
  // otherwise a half-voxel search of [t_a - 1, t_b + 1] finds it. Writes pixel i's outputs.
  VF_HD bool refineCrossing(Vec3f o, Vec3f d, float t_a, float t_b, int i) const {
    float s_a, s_b;
    bool bracketed = sampleTsdf(volume, o + d * t_a, s_a) && sampleTsdf(volume, o + d * t_b, s_b) &&
                     s_a > 0.f && s_b <= 0.f;
    if (!bracketed) {
      bool have_prev = false;
      for (float t = t_a - 1.f; t <= t_b + 1.f; t += 0.5f) {
        float s;
        if (!sampleTsdf(volume, o + d * t, s)) {
          have_prev = false;
          continue;
        }
        if (have_prev && s_a > 0.f && s <= 0.f) {
          t_b = t;
          s_b = s;
          bracketed = true;
          break;
        }
        if (have_prev && s_a < 0.f && s > 0.f) return true;  // back face: nothing visible
        t_a = t;
        s_a = s;
        have_prev = true;
      }
      if (!bracketed) return false;
    }
    float t_hit = t_a + s_a * (t_b - t_a) / (s_a - s_b);
    float s_hit;
    Vec3f gradient;
    if (!sampleTsdfGradient(volume, o + d * t_hit, s_hit, gradient)) return true;
    if (s_hit > 0.f) t_hit = t_hit + s_hit * (t_b - t_hit) / (s_hit - s_b);
    else t_hit = t_a + s_a * (t_hit - t_a) / (s_a - s_hit);
    const float g_norm = norm(gradient);
    if (!(g_norm > 1e-6f)) return true;
    vertex[i] = T_world_cam.t + d * (t_hit * volume.voxel_size_m);
    normal[i] = gradient * (1.f / g_norm);
    if (color.data) {
      Rgb8 c;
      if (nearestColor(volume, o + d * t_hit, c)) color[i] = Rgb8{c.r, c.g, c.b, 255};
    }
    return true;
  }
};

// Nearest-neighbour half-resolution copy of the predicted vertex / normal maps, for the ICP
// pyramid.
struct DownsamplePredictionKernel {
  ImageView<const Vec3f> fine_vertex, fine_normal;
  ImageView<Vec3f> coarse_vertex, coarse_normal;

  VF_HD void operator()(int i) const {
    const int x = i % coarse_vertex.width, y = i / coarse_vertex.width;
    coarse_vertex[i] = fine_vertex(2 * x, 2 * y);
    coarse_normal[i] = fine_normal(2 * x, 2 * y);
  }
};

}  // namespace vf
