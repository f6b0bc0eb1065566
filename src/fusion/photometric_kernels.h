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
  VF_HD int rowLength() const { return coarse.width; }
  VF_HD void operator()(int i) const { at(i % coarse.width, i / coarse.width, i); }
  VF_HD void at(int x, int y, int i) const {
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
  VF_HD int rowLength() const { return coarse.width; }
  VF_HD void operator()(int i) const { at(i % coarse.width, i / coarse.width, i); }
  VF_HD void at(int x, int y, int i) const {
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
  VF_HD int rowLength() const { return intensity.width; }
  VF_HD void operator()(int i) const { at(i % intensity.width, i / intensity.width, i); }
  // Without branches (border reads clamped to the image, their result replaced by NaN), so that
  // the CPU compiler can run a row in vector lanes.
  VF_HD void at(int x, int y, int i) const {
    const int w = intensity.width, h = intensity.height;
    const bool inside = (x >= 1) & (y >= 1) & (x + 1 < w) & (y + 1 < h);
    const int xl = x >= 1 ? x - 1 : x, xr = x + 1 < w ? x + 1 : x;
    const int yu = y >= 1 ? y - 1 : y, yd = y + 1 < h ? y + 1 : y;
    const float l = intensity(xl, y), r = intensity(xr, y), u = intensity(x, yu), d = intensity(x, yd);
    const bool valid = inside & (l >= 0.f) & (r >= 0.f) & (u >= 0.f) & (d >= 0.f);
    const float nan = quietNaN();
    gradient[i] = Vec2f{valid ? 0.5f * (r - l) : nan, valid ? 0.5f * (d - u) : nan};
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

  // One model pixel's row (CUDA's reduction, one item per thread).
  VF_HD bool operator()(int item, float* row) const { return singleRow(*this, item, row); }

  // The rows of items first .. first + L - 1 (zero from `items` on), one lane each, row[k][lane]:
  // branch-free, as IcpKernel::rows, so that the CPU runs L pixels in vector lanes. False when
  // no lane has a model point with colour.
  template <int L>
  VF_HD bool rows(int first, int items, float (&row)[normal_row::kSize][L]) const {
    int pixel[L], usable[L];
    float grey_model[L], px[L], py[L], pz[L];
    for (int j = 0; j < L; ++j)
      pixel[j] = stridedPixel(first + j < items ? first + j : first, model_vertex.width, stride_px);
    int any = 0;
    for (int j = 0; j < L; ++j) {
      const Vec3f n = model_normal[pixel[j]], p = model_vertex[pixel[j]];
      grey_model[j] = model_intensity[pixel[j]];
      px[j] = p.x, py[j] = p.y, pz[j] = p.z;
      usable[j] = (first + j < items) & !((n.x == 0.f) & (n.y == 0.f) & (n.z == 0.f)) & !(grey_model[j] < 0.f);
      any |= usable[j];
    }
    if (!any) return false;
    // Where each model point lands in the current image; sample positions clamped into the
    // image where refused, so that every read below is in bounds.
    float cx[L], cy[L], cz[L], u[L], v[L];
    int depth_pixel[L];
    for (int j = 0; j < L; ++j) {
      const Vec3f pc = T_cam_world * Vec3f{px[j], py[j], pz[j]};
      cx[j] = pc.x, cy[j] = pc.y, cz[j] = pc.z;
      float uj, vj;
      intrinsics.projectAnyDepth(pc, uj, vj);
      usable[j] &= (pc.z > 0.f) & (uj >= 1.f) & (vj >= 1.f) & (uj < float(intensity.width - 2)) &
                   (vj < float(intensity.height - 2));
      u[j] = usable[j] ? uj : 1.f;
      v[j] = usable[j] ? vj : 1.f;
      depth_pixel[j] = int(v[j] + 0.5f) * depth.width + int(u[j] + 0.5f);
    }
    float d[L], grey[L], gx[L], gy[L];
    for (int j = 0; j < L; ++j) d[j] = depth[depth_pixel[j]];
    for (int j = 0; j < L; ++j) {
      grey[j] = bilinear(intensity, u[j], v[j]);
      const Vec2f g = bilinear(gradient, u[j], v[j]);
      gx[j] = g.x, gy[j] = g.y;
    }
    float J[6][L], r[L], w[L];
    for (int j = 0; j < L; ++j) {
      // Occluded or unseen; no colour here or at a neighbour (a NaN gradient).
      const int ok = usable[j] & (d[j] > 0.f) & !(fabsf(d[j] - cz[j]) > max_depth_difference_m) & !(grey[j] < 0.f) &
                     (gx[j] == gx[j]) & (gy[j] == gy[j]);
      r[j] = ok ? grey[j] - grey_model[j] : 0.f;
      const float inv_z = 1.f / (ok ? cz[j] : 1.f);
      const float gxs = ok ? gx[j] : 0.f, gys = ok ? gy[j] : 0.f;
      // d(grey)/d(p_cam) through the pinhole projection, then into the world frame.
      const Vec3f g_cam{gxs * intrinsics.fx * inv_z, gys * intrinsics.fy * inv_z,
                        -(gxs * intrinsics.fx * cx[j] + gys * intrinsics.fy * cy[j]) * inv_z * inv_z};
      const Vec3f a = T_world_cam.rotate(g_cam);
      // cross(a, p), then -a; zero where refused, whatever the refused lane's point held.
      J[0][j] = ok ? a.y * pz[j] - a.z * py[j] : 0.f;
      J[1][j] = ok ? a.z * px[j] - a.x * pz[j] : 0.f;
      J[2][j] = ok ? a.x * py[j] - a.y * px[j] : 0.f;
      J[3][j] = ok ? -a.x : 0.f, J[4][j] = ok ? -a.y : 0.f, J[5][j] = ok ? -a.z : 0.f;
      const float abs_r = fabsf(r[j]);
      w[j] = ok ? weight * (abs_r <= huber ? 1.f : huber / maxFloat(abs_r, huber)) : 0.f;
      row[normal_row::kInliers][j] = 0.f;  // statistics (inliers, measured pixels) stay geometric
      row[normal_row::kMeasured][j] = 0.f;
      row[normal_row::kCovered][j] = 0.f;
    }
    packNormalRows<L>(row, J, r, w);
    return true;
  }
};

}  // namespace vf
