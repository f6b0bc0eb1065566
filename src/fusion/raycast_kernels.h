#pragma once
// Surface prediction (KinectFusion section 3.4): march each pixel's ray through the TSDF until a
// +/- zero crossing, refine it by linear interpolation (eq. 15), take normals from the TSDF
// gradient. Empty space is skipped a whole brick at a time: a brick no frame touched has no
// surface.
#include "core/image.h"
#include "core/intrinsics.h"
#include "fusion/atomics.h"
#include "fusion/fast_math.h"
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

// A brick's bounding sphere against the camera's frustum (near, far and the four image edges),
// before the exact projection of its corners: most bricks of a large scene are out of view and
// cost one transform.
struct FrustumCull {
  float near_m = 0.1f, far_m = 5.f;
  Vec3f side_normals[4];  // camera frame, unit, pointing out of the frustum through each image edge

  static FrustumCull make(const Intrinsics& k, float near_m, float far_m) {
    FrustumCull c;
    c.near_m = near_m;
    c.far_m = far_m;
    const float left = -0.5f - k.cx, right = float(k.width) - 0.5f - k.cx;
    const float top = -0.5f - k.cy, bottom = float(k.height) - 0.5f - k.cy;
    c.side_normals[0] = normalized(Vec3f{-k.fx, 0.f, left});
    c.side_normals[1] = normalized(Vec3f{k.fx, 0.f, -right});
    c.side_normals[2] = normalized(Vec3f{0.f, -k.fy, top});
    c.side_normals[3] = normalized(Vec3f{0.f, k.fy, -bottom});
    return c;
  }
  VF_HD bool outside(Vec3f center_cam, float radius) const {
    if (center_cam.z + radius < near_m || center_cam.z - radius > far_m) return true;
    for (int k = 0; k < 4; ++k)
      if (dot(side_normals[k], center_cam) > radius) return true;
    return false;
  }
};

struct BrickRangeKernel {
  VolumeView volume;
  const int* slots = nullptr;  // the bricks to project (SparseVolume::bricksNearView); null: every slot
  Intrinsics intrinsics;
  Rigid3f T_cam_world;
  FrustumCull cull;
  float* range_min;
  float* range_max;
  int tiles_x = 0, tiles_y = 0;

  VF_HD void operator()(int i) const {
    const Vec3i origin = volume.brickOrigin(slots ? slots[i] : i);
    const float edge_m = kBrickSize * volume.voxel_size_m;
    const Vec3f corner0{origin.x * volume.voxel_size_m, origin.y * volume.voxel_size_m, origin.z * volume.voxel_size_m};
    const Vec3f center = T_cam_world * (corner0 + Vec3f{0.5f, 0.5f, 0.5f} * edge_m);
    if (cull.outside(center, 0.8661f * edge_m)) return;  // radius: half the diagonal
    const float near_m = cull.near_m;
    float z_lo = 3.0e38f, z_hi = 0.f, u_lo = 3.0e38f, u_hi = -3.0e38f, v_lo = 3.0e38f, v_hi = -3.0e38f;
    bool behind = false;
    for (int k = 0; k < 8; ++k) {
      // Brick corners: the outer faces of its edge voxels.
      const Vec3f world = corner0 + Vec3f{(k & 1) ? edge_m : 0.f, (k & 2) ? edge_m : 0.f, (k & 4) ? edge_m : 0.f};
      const Vec3f p = T_cam_world * world;
      z_lo = p.z < z_lo ? p.z : z_lo;
      z_hi = p.z > z_hi ? p.z : z_hi;
      if (p.z < near_m) {
        behind = true;
        continue;
      }
      float u = 0.f, v = 0.f;  // p.z >= near_m > 0: project() always sets them
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
    const int tx0 = clampInt(int(floorf(maxFloat(u_lo, -8.f) / kRangeTilePx)), 0, tiles_x);
    const int tx1 = clampInt(int(floorf(minFloat(u_hi, 1.0e6f) / kRangeTilePx)), -1, tiles_x - 1);
    const int ty0 = clampInt(int(floorf(maxFloat(v_lo, -8.f) / kRangeTilePx)), 0, tiles_y);
    const int ty1 = clampInt(int(floorf(minFloat(v_hi, 1.0e6f) / kRangeTilePx)), -1, tiles_y - 1);
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
  // Optional (data may be null): a depth image of this camera and level. Where it holds a
  // depth d, the ray only looks for a surface within [d - window_m, d + window_m]; in a hole,
  // within the window of the depths measured up to kWindowHoleRadiusPx pixels away, and where
  // there are none, it casts no ray at all (Pipeline::raycastForTracking says why).
  ImageView<const float> window_depth;
  float window_m = 0.f;
  static constexpr int kWindowHoleRadiusPx = 2;

  // Ray parameter where the ray leaves brick (bx, by, bz).
  VF_HD static float brickExit(Vec3f o, Vec3f d, int bx, int by, int bz) {
    const float oo[3] = {o.x, o.y, o.z}, dd[3] = {d.x, d.y, d.z};
    const int b[3] = {bx, by, bz};
    float t = 3.0e38f;
    for (int a = 0; a < 3; ++a) {
      if (fabsf(dd[a]) < 1e-9f) continue;
      const float face = dd[a] > 0.f ? float(b[a] * kBrickSize) + (kBrickSize - 0.5f) : float(b[a] * kBrickSize) - 0.5f;
      const float ta = (face - oo[a]) / dd[a];
      t = ta < t ? ta : t;
    }
    return t;
  }

  // Rays marched together by one work item. Each step of a ray waits for a voxel read from
  // anywhere in the pool (a cache miss, most of the raycast's time); stepping several rays in
  // turn keeps that many reads in flight at once. The rays do not interact, so each gives the
  // same result whatever the count: the CPU uses kMaxRaysPerItem, CUDA one ray per thread.
  static constexpr int kMaxRaysPerItem = 4;
  int rays_per_item = 1;  // 1 .. kMaxRaysPerItem

  // One pixel's march: t in voxels along the unit ray o + d t, up to t_end.
  struct Ray {
    Vec3f o, d;
    float t, t_end, prev_t, prev_sdf;  // prev_*: the last positive read (voxels)
    bool have_prev;
    Vec3i brick;  // the brick of the last lookup and its slot (-2: nothing looked up yet)
    int slot;
    int pixel;
  };

  VF_HD void operator()(int item) const {
    Ray rays[kMaxRaysPerItem];
    bool active[kMaxRaysPerItem];
    const int pixels = vertex.width * vertex.height;
    for (int k = 0; k < rays_per_item; ++k) {
      const int i = item * rays_per_item + k;
      active[k] = i < pixels && begin(i, rays[k]);
    }
    for (bool any = true; any;) {
      any = false;
      for (int k = 0; k < rays_per_item; ++k)
        if (active[k]) any |= active[k] = advance(rays[k]);
    }
  }

  // Clears pixel i's outputs and sets up its ray; false when no allocated brick projects there.
  VF_HD bool begin(int i, Ray& r) const {
    const int x = i % vertex.width, y = i / vertex.width;
    normal[i] = Vec3f{0.f, 0.f, 0.f};
    vertex[i] = Vec3f{0.f, 0.f, 0.f};
    if (color.data) color[i] = Rgb8{0, 0, 0, 0};
    // March in voxel units: o and d in voxel coordinates, t in voxels along a unit voxel ray.
    const Vec3f ray_world = T_world_cam.rotate(normalized(intrinsics.backProject(float(x), float(y), 1.f)));
    const float inv_voxel = 1.f / volume.voxel_size_m;
    r.o = volume.toVoxel(T_world_cam.t);
    r.d = ray_world;
    r.t = near_m * inv_voxel;
    r.t_end = far_m * inv_voxel;
    const int tile = (y / kRangeTilePx) * tiles_x + x / kRangeTilePx;
    const float z_lo = range_min[tile], z_hi = range_max[tile];
    if (z_lo > z_hi) return false;  // no allocated brick projects here
    // Depth z along this pixel's ray is t * |ray_cam| with ray_cam = (.., .., 1); one voxel of slack.
    const float z_to_t = norm(intrinsics.backProject(float(x), float(y), 1.f)) * inv_voxel;
    r.t = maxFloat(r.t, z_lo * z_to_t - 1.f);
    r.t_end = minFloat(r.t_end, z_hi * z_to_t + 1.f);
    if (window_depth.data) {
      float d_lo, d_hi;
      if (!windowDepths(x, y, d_lo, d_hi)) return false;
      r.t = maxFloat(r.t, (d_lo - window_m) * z_to_t);
      r.t_end = minFloat(r.t_end, (d_hi + window_m) * z_to_t);
      if (!(r.t < r.t_end)) return false;
    }
    r.prev_t = r.prev_sdf = 0.f;
    r.have_prev = false;
    r.brick = Vec3i{0, 0, 0};
    r.slot = -2;
    r.pixel = i;
    return true;
  }

  // The nearest and farthest depth measured at pixel (x, y) of window_depth or, where it has
  // none, in the square of kWindowHoleRadiusPx around it; false when there is none.
  VF_HD bool windowDepths(int x, int y, float& d_lo, float& d_hi) const {
    d_lo = d_hi = window_depth(x, y);
    if (d_lo > 0.f) return true;
    const int r = kWindowHoleRadiusPx;
    d_lo = 3.0e38f, d_hi = 0.f;
    for (int yy = y - r > 0 ? y - r : 0; yy <= y + r && yy < window_depth.height; ++yy)
      for (int xx = x - r > 0 ? x - r : 0; xx <= x + r && xx < window_depth.width; ++xx) {
        const float d = window_depth(xx, yy);
        if (d > 0.f) d_lo = minFloat(d_lo, d), d_hi = maxFloat(d_hi, d);
      }
    return d_hi > 0.f;
  }

  // One step of the coarse march on single nearest-voxel reads (one load each); the trilinear
  // field is only evaluated once a sign change is bracketed. False once the ray is done: it hit
  // (outputs written) or left its range.
  VF_HD bool advance(Ray& r) const {
    if (!(r.t < r.t_end)) return false;
    const Vec3f g = r.o + r.d * r.t;
    const int ix = int(floorf(g.x + 0.5f)), iy = int(floorf(g.y + 0.5f)), iz = int(floorf(g.z + 0.5f));
    const Vec3i brick = brickOfVoxel(ix, iy, iz);
    if (r.slot == -2 || brick.x != r.brick.x || brick.y != r.brick.y || brick.z != r.brick.z) {
      r.brick = brick;  // look a brick up once, not at every step inside it
      r.slot = volume.slotOf(brick);
    }
    if (r.slot < 0) {
      // Never advance less than a regular step: a ray grazing a brick face would otherwise
      // creep along it in tiny increments.
      const float t_exit = brickExit(r.o, r.d, brick.x, brick.y, brick.z);
      r.t = t_exit > r.t + min_step_vox ? t_exit + 0.01f : r.t + min_step_vox;
      r.have_prev = false;
      return true;
    }
    const float trunc_vox = volume.truncation_m * (1.f / volume.voxel_size_m);
    const TsdfVoxel v = volume.tsdf[VolumeView::voxelIndex(r.slot, localVoxelIndex(ix, iy, iz))];
    if (v.weight == 0) {
      // Unobserved: no surface within half a truncation band can start here unseen, since
      // every fused surface is preceded by a full band of positive voxels.
      r.t += maxFloat(min_step_vox, 0.5f * trunc_vox);
      r.have_prev = false;
      return true;
    }
    const float sdf = float(v.tsdf) * (trunc_vox / kTsdfScale);  // voxels
    if (sdf <= 0.f) {
      if (!r.have_prev) {  // entered behind a surface (or a back face): keep looking
        r.t += min_step_vox;
        return true;
      }
      if (newtonCrossing(r.o, r.d, r.prev_t, r.prev_sdf, r.t, sdf, r.pixel) ||
          refineCrossing(r.o, r.d, r.prev_t, r.t + 1.f, r.pixel))
        return false;
      r.have_prev = false;  // no trilinear crossing here after all: move on
      r.t += min_step_vox;
      return true;
    }
    r.prev_t = r.t;
    r.prev_sdf = sdf;
    r.have_prev = true;
    const float step = sdf * step_fraction;
    r.t += step > min_step_vox ? step : min_step_vox;
    return true;
  }

  // The crossing between t_a (in front, nearest-voxel distance sdf_a > 0) and t_b (behind,
  // sdf_b <= 0), in one trilinear read: the secant of the two reads puts it within a voxel, and
  // one Newton step along the ray on the trilinear value and gradient there lands on it. Writes
  // pixel i's outputs and returns true, or false where that is not safe (a flat or rising
  // field, a step longer than a voxel, an unobserved corner, an unseen back): refineCrossing
  // decides then. Two of refineCrossing's three trilinear reads saved: fr1_xyz raycast 15.5 ->
  // 11.9 ms, ATE 0.975 -> 0.979 cm (teddy 0.315 -> 0.307, Replica 0.019 -> 0.016).
  VF_HD bool newtonCrossing(Vec3f o, Vec3f d, float t_a, float sdf_a, float t_b, float sdf_b, int i) const {
    const float t0 = t_a + sdf_a * (t_b - t_a) / (sdf_a - sdf_b);
    float s0;
    Vec3f gradient;
    if (!sampleTsdfGradient(volume, o + d * t0, s0, gradient)) return false;
    const float slope = dot(gradient, d);  // d(tsdf)/dt; the field falls through a front face
    const float g_norm = norm(gradient);
    if (!(slope < -0.1f * g_norm) || !(g_norm > 1e-6f)) return false;
    const float dt = -s0 / slope;
    if (!(fabsf(dt) <= 1.f)) return false;
    // Where the voxels one and two steps behind were never observed (the rim of what the camera
    // saw), the gradient leans towards the unseen side: refineCrossing, which needs that side
    // observed, decides (the fused sphere's rim normals were 30 degrees off otherwise).
    if (!observedVoxel(o + d * (t_b + 1.f)) || !observedVoxel(o + d * (t_b + 2.f))) return false;
    writeHit(o, d, t0 + dt, gradient * (1.f / g_norm), i);
    return true;
  }

  VF_HD bool observedVoxel(Vec3f g) const {
    const int64_t index = nearestVoxel(volume, g);
    return index >= 0 && volume.tsdf[index].weight > 0;
  }

  VF_HD void writeHit(Vec3f o, Vec3f d, float t_hit, Vec3f unit_normal, int i) const {
    vertex[i] = T_world_cam.t + d * (t_hit * volume.voxel_size_m);
    normal[i] = unit_normal;
    if (color.data) {
      Rgb8 c;
      if (nearestColor(volume, o + d * t_hit, c)) color[i] = Rgb8{c.r, c.g, c.b, 255};
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
    writeHit(o, d, t_hit, gradient * (1.f / g_norm), i);
    return true;
  }
};

// Nearest-neighbour half-resolution copy of the predicted vertex / normal maps, for the ICP
// pyramid.
struct DownsamplePredictionKernel {
  ImageView<const Vec3f> fine_vertex, fine_normal;
  ImageView<Vec3f> coarse_vertex, coarse_normal;

  VF_HD int rowLength() const { return coarse_vertex.width; }
  VF_HD void operator()(int i) const { at(i % coarse_vertex.width, i / coarse_vertex.width, i); }
  VF_HD void at(int x, int y, int i) const {
    coarse_vertex[i] = fine_vertex(2 * x, 2 * y);
    coarse_normal[i] = fine_normal(2 * x, 2 * y);
  }
};

}  // namespace vf
