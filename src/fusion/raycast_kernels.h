#pragma once
// Surface prediction (KinectFusion section 3.4): march each pixel's ray through the TSDF until a
// +/- zero crossing, refine it by linear interpolation (eq. 15), take normals from the TSDF
// gradient. Empty space is skipped a whole brick at a time: a brick no frame touched has no
// surface.
#include "core/image.h"
#include "core/intrinsics.h"
#include "fusion/volume_sampling.h"

namespace vf {

struct RaycastKernel {
  VolumeView volume;
  Intrinsics intrinsics;
  Rigid3f T_world_cam;
  float near_m = 0.2f, far_m = 5.f;
  float min_step_vox = 0.8f, step_fraction = 0.8f;
  ImageView<Vec3f> vertex;  // world frame
  ImageView<Vec3f> normal;  // world frame; (0,0,0) marks "no surface"
  ImageView<Rgb8> color;    // data may be null

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
    if (!clipToVolume(o, d, t, t_end)) return;
    const float trunc_vox = volume.truncation_m * inv_voxel;
    float prev_t = 0.f, prev_sdf = 0.f;
    bool have_prev = false;
    while (t < t_end) {
      const Vec3f g = o + d * t;
      const int ix = int(floorf(g.x + 0.5f)), iy = int(floorf(g.y + 0.5f)), iz = int(floorf(g.z + 0.5f));
      if (!volume.contains(ix, iy, iz)) {
        t += min_step_vox;
        have_prev = false;
        continue;
      }
      const int bx = ix >> 3, by = iy >> 3, bz = iz >> 3;
      if (volume.brick_stamp[volume.brickIndex(bx, by, bz)] == 0) {
        t = brickExit(o, d, bx, by, bz) + 0.01f;
        have_prev = false;
        continue;
      }
      float s;
      if (!sampleTsdf(volume, g, s)) {
        t += min_step_vox;
        have_prev = false;
        continue;
      }
      const float sdf = s * trunc_vox;  // voxels
      if (have_prev && prev_sdf > 0.f && sdf <= 0.f) {
        float t_hit = prev_t + prev_sdf * (t - prev_t) / (prev_sdf - sdf);
        // One secant refinement on the interpolated field sharpens the crossing.
        float s_hit;
        if (sampleTsdf(volume, o + d * t_hit, s_hit)) {
          const float sdf_hit = s_hit * trunc_vox;
          if (sdf_hit > 0.f) t_hit = t_hit + sdf_hit * (t - t_hit) / (sdf_hit - sdf);
          else t_hit = prev_t + prev_sdf * (t_hit - prev_t) / (prev_sdf - sdf_hit);
        }
        const Vec3f hit = o + d * t_hit;
        Vec3f n;
        if (!tsdfNormal(volume, hit, n)) return;
        vertex[i] = T_world_cam.t + ray_world * (t_hit * volume.voxel_size_m);
        normal[i] = n;
        if (color.data) {
          Rgb8 c;
          if (nearestColor(volume, hit, c)) color[i] = Rgb8{c.r, c.g, c.b, 255};
        }
        return;
      }
      if (have_prev && prev_sdf < 0.f && sdf > 0.f) return;  // left a back face: nothing visible
      prev_t = t;
      prev_sdf = sdf;
      have_prev = true;
      const float step = sdf * step_fraction;
      t += step > min_step_vox ? step : min_step_vox;
    }
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
