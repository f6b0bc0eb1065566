#pragma once
// The photometric half of tracking: model points carry the colour fused into the volume; the
// current image should show the same intensity where they project. Geometry alone leaves a
// camera free to slide along large planes (a desk, a wall); texture pins it down. The residual
// and Jacobian follow dense RGB-D odometry (Steinbruecker et al. 2011, Kerl et al. 2013), the
// model side comes from the raycast as in colour-aware KinectFusion variants.
#include "core/image.h"
#include "core/intrinsics.h"
#include "fusion/fast_math.h"
#include "fusion/icp_kernels.h"

namespace vf {

// Grey level in [0, 1] from sRGB bytes (Rec. 601 weights); pixels without colour (alpha 0,
// e.g. model pixels no frame coloured) become -1 so the photometric term skips them.
struct IntensityKernel {
  ImageView<const Rgb8> color;
  ImageView<float> intensity;
  VF_HD void operator()(int i) const {
    const Rgb8 c = color[i];
    intensity[i] = c.a == 0 ? -1.f : (0.299f * c.r + 0.587f * c.g + 0.114f * c.b) * (1.f / 255.f);
  }
};

// Half resolution: the mean of the 2x2 block's valid pixels (-1 when none is valid).
struct DownsampleIntensityKernel {
  ImageView<const float> fine;
  ImageView<float> coarse;
  VF_HD void operator()(int i) const {
    const int x = i % coarse.width, y = i / coarse.width;
    float sum = 0.f;
    int count = 0;
    for (int k = 0; k < 4; ++k) {
      const float v = fine(2 * x + (k & 1), 2 * y + (k >> 1));
      if (v >= 0.f) sum += v, ++count;
    }
    coarse[i] = count ? sum / float(count) : -1.f;
  }
};

// Nearest-neighbour half resolution, matching DownsamplePredictionKernel for the model's pixels.
struct DownsampleModelIntensityKernel {
  ImageView<const float> fine;
  ImageView<float> coarse;
  VF_HD void operator()(int i) const {
    const int x = i % coarse.width, y = i / coarse.width;
    coarse[i] = fine(2 * x, 2 * y);
  }
};

// The image gradient by central differences, (dI/dx, dI/dy) per pixel; NaN where a neighbour
// has no colour or lies outside. Computed once per frame and level: the photometric term then
// interpolates it instead of differencing four interpolated intensities at every iteration
// (bilinear interpolation is linear, so the two agree up to rounding).
struct IntensityGradientKernel {
  ImageView<const float> intensity;
  ImageView<Vec2f> gradient;
  VF_HD void operator()(int i) const {
    const int x = i % intensity.width, y = i / intensity.width;
    const float nan = quietNaN();
    if (x < 1 || y < 1 || x + 1 >= intensity.width || y + 1 >= intensity.height) {
      gradient[i] = Vec2f{nan, nan};
      return;
    }
    const float l = intensity(x - 1, y), r = intensity(x + 1, y), u = intensity(x, y - 1), d = intensity(x, y + 1);
    gradient[i] = l < 0.f || r < 0.f || u < 0.f || d < 0.f ? Vec2f{nan, nan} : Vec2f{0.5f * (r - l), 0.5f * (d - u)};
  }
};

VF_HD float bilinear(const ImageView<const float>& img, float u, float v) {
  const int x = int(floorf(u)), y = int(floorf(v));
  const float fx = u - float(x), fy = v - float(y);
  const float a = img(x, y), b = img(x + 1, y), c = img(x, y + 1), d = img(x + 1, y + 1);
  return (a + fx * (b - a)) + fy * ((c + fx * (d - c)) - (a + fx * (b - a)));
}

VF_HD Vec2f bilinear(const ImageView<const Vec2f>& img, float u, float v) {
  const int x = int(floorf(u)), y = int(floorf(v));
  const float fx = u - float(x), fy = v - float(y);
  const Vec2f a = img(x, y), b = img(x + 1, y), c = img(x, y + 1), d = img(x + 1, y + 1);
  auto lerp2 = [&](float p, float q, float r, float s) { return (p + fx * (q - p)) + fy * ((r + fx * (s - r)) - (p + fx * (q - p))); };
  return {lerp2(a.x, b.x, c.x, d.x), lerp2(a.y, b.y, c.y, d.y)};
}

// One model pixel: r = I_current(project(T_cam_world * p)) - I_model, weighted into the same
// row layout as IcpKernel (increment applied on the left in world coordinates).
struct PhotometricKernel {
  ImageView<const Vec3f> model_vertex;  // world frame, level l
  ImageView<const Vec3f> model_normal;
  ImageView<const float> model_intensity;
  ImageView<const float> intensity;     // current frame, level l
  ImageView<const Vec2f> gradient;      // its IntensityGradientKernel
  ImageView<const float> depth;         // current frame (filtered), level l: occlusion test
  Intrinsics intrinsics;                // current camera, level l
  Rigid3f T_world_cam;                  // current estimate
  Rigid3f T_cam_world;
  float weight = 0.f;                   // relative to the point-to-plane term (m^2 per grey^2)
  float huber = 0.1f;                   // grey levels
  float max_depth_difference_m = 0.05f;
  int stride_px = 1;  // use every stride-th model pixel in x and y

  // Number of work items for the reduction.
  VF_HD int count() const { return stridedPixelCount(model_vertex.width, model_vertex.height, stride_px); }

  VF_HD bool operator()(int item, float* row) const {
    const int i = stridedPixel(item, model_vertex.width, stride_px);
    const Vec3f n = model_normal[i];
    if (n.x == 0.f && n.y == 0.f && n.z == 0.f) return false;
    const float model_grey = model_intensity[i];
    if (model_grey < 0.f) return false;
    const Vec3f p = model_vertex[i];
    const Vec3f pc = T_cam_world * p;
    float u, v;
    if (!intrinsics.project(pc, u, v)) return false;
    if (!(u >= 1.f && v >= 1.f && u < float(intensity.width - 2) && v < float(intensity.height - 2))) return false;
    const float d = depth(int(u + 0.5f), int(v + 0.5f));
    if (d <= 0.f || fabsf(d - pc.z) > max_depth_difference_m) return false;  // occluded or unseen
    const float grey = bilinear(intensity, u, v);
    const Vec2f g = bilinear(gradient, u, v);
    if (grey < 0.f || !(g.x == g.x && g.y == g.y)) return false;  // no colour here or at a neighbour (NaN)
    const float gx = g.x, gy = g.y;
    const float r = grey - model_grey;
    const float inv_z = 1.f / pc.z;
    // d(grey)/d(p_cam) through the pinhole projection.
    const Vec3f g_cam{gx * intrinsics.fx * inv_z, gy * intrinsics.fy * inv_z,
                      -(gx * intrinsics.fx * pc.x + gy * intrinsics.fy * pc.y) * inv_z * inv_z};
    const Vec3f a = T_world_cam.rotate(g_cam);
    const Vec3f j_rot = cross(a, p);
    const float J[6] = {j_rot.x, j_rot.y, j_rot.z, -a.x, -a.y, -a.z};
    const float abs_r = fabsf(r);
    const float w = weight * (abs_r <= huber ? 1.f : huber / abs_r);
    packNormalRow(row, J, r, w);
    row[normal_row::kInliers] = 0.f;  // statistics (inliers, measured pixels) stay geometric
    row[normal_row::kMeasured] = 0.f;
    return true;
  }
};

}  // namespace vf
