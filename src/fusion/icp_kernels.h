#pragma once
// Sensor pose estimation (KinectFusion section 3.5): projective data association against the
// raycast prediction and the point-to-plane error, eq. (16), linearised around the current
// estimate. Each pixel contributes one row of the 6x6 normal equations.
#include "core/image.h"
#include "core/intrinsics.h"
#include "fusion/fast_math.h"
#include "fusion/normal_equations.h"

namespace vf {

struct IcpKernel {
  ImageView<const Vec3f> vertex_cam;   // measured, current camera frame, level l
  ImageView<const Vec3f> normal_cam;
  ImageView<const Vec3f> model_vertex; // predicted, world frame, level l
  ImageView<const Vec3f> model_normal;
  Intrinsics model_intrinsics;          // camera of the prediction at level l
  Rigid3f T_world_cam;                  // current estimate
  Rigid3f T_model_world;                // inverse of the prediction's camera pose
  float max_distance_m = 0.1f;
  float min_normal_cos = 0.866f;
  float huber_m = 0.02f;
  // Axial depth noise sigma(z) = noise_sigma0_m + noise_sigma_quadratic * (z - 0.4)^2 (Nguyen,
  // Izadi and Lovell 2012); each residual is scaled by sigma(1 m) / sigma(z) before the Huber
  // weight, so that a far, coarsely quantised reading counts for what it measures. 0 = off.
  float noise_sigma_quadratic = 0.f;
  float noise_sigma0_m = 0.0012f;
  int noise_weight_power = 2;  // weight (sigma(1 m) / sigma(z))^power: 2 = inverse variance

  int stride_px = 1;  // use every stride-th measured pixel in x and y

  // Number of work items for the reduction.
  VF_HD int count() const { return stridedPixelCount(vertex_cam.width, vertex_cam.height, stride_px); }

  // One pixel's row (CUDA's reduction, one item per thread).
  VF_HD bool operator()(int item, float* row) const { return singleRow(*this, item, row); }

  // The rows of items first .. first + L - 1 (those from `items` on give zero rows), one lane each:
  // row[k][lane]. Written without branches, with every lane computing and the rejected ones
  // weighted zero, so that the CPU compiler runs L pixels in vector lanes (the CPU reduction
  // takes 8 at a time). The image reads get loops of their own, as in IntegrateKernel::fuseRow.
  // False when no lane has a measurement.
  template <int L>
  VF_HD bool rows(int first, int items, float (&row)[normal_row::kSize][L]) const {
    int pixel[L], measured[L];
    float vx[L], vy[L], vz[L], nx[L], ny[L], nz[L];
    for (int j = 0; j < L; ++j) pixel[j] = stridedPixel(first + j < items ? first + j : first, vertex_cam.width, stride_px);
    for (int j = 0; j < L; ++j) {
      const Vec3f v = vertex_cam[pixel[j]], n = normal_cam[pixel[j]];
      vx[j] = v.x, vy[j] = v.y, vz[j] = v.z, nx[j] = n.x, ny[j] = n.y, nz[j] = n.z;
    }
    int any_measured = 0;
    for (int j = 0; j < L; ++j) {
      measured[j] = (first + j < items) & (vz[j] > 0.f) & !((nx[j] == 0.f) & (ny[j] == 0.f) & (nz[j] == 0.f));
      any_measured |= measured[j];
    }
    if (!any_measured) return false;
    // World point and normal; the model pixel the point projects to.
    float wx[L], wy[L], wz[L], wnx[L], wny[L], wnz[L];
    int model_pixel[L], found[L];
    for (int j = 0; j < L; ++j) {
      const Vec3f v = T_world_cam * Vec3f{vx[j], vy[j], vz[j]};
      const Vec3f n = T_world_cam.rotate(Vec3f{nx[j], ny[j], nz[j]});
      wx[j] = v.x, wy[j] = v.y, wz[j] = v.z, wnx[j] = n.x, wny[j] = n.y, wnz[j] = n.z;
      const Vec3f m = T_model_world * v;
      float u, w;
      model_intrinsics.projectAnyDepth(m, u, w);
      const int inside = measured[j] & (m.z > 0.f) & (u >= -0.5f) & (w >= -0.5f) &
                         (u < float(model_vertex.width) - 0.5f) & (w < float(model_vertex.height) - 0.5f);
      const float us = inside ? u : 0.f, ws = inside ? w : 0.f;  // finite, so the pixel below is in the image
      model_pixel[j] = int(floorf(ws + 0.5f)) * model_vertex.width + int(floorf(us + 0.5f));
      found[j] = inside;
    }
    float mx[L], my[L], mz[L], mnx[L], mny[L], mnz[L];
    for (int j = 0; j < L; ++j) {
      const Vec3f mv = model_vertex[model_pixel[j]], mn = model_normal[model_pixel[j]];
      mx[j] = mv.x, my[j] = mv.y, mz[j] = mv.z, mnx[j] = mn.x, mny[j] = mn.y, mnz[j] = mn.z;
    }
    const float max_d2 = max_distance_m * max_distance_m;
    float J[6][L], r[L], weight[L], robust[L];
    for (int j = 0; j < L; ++j) {
      const float dx = wx[j] - mx[j], dy = wy[j] - my[j], dz = wz[j] - mz[j];
      const int paired = found[j] & !((mnx[j] == 0.f) & (mny[j] == 0.f) & (mnz[j] == 0.f)) &
                         !(dx * dx + dy * dy + dz * dz > max_d2) &
                         !(wnx[j] * mnx[j] + wny[j] * mny[j] + wnz[j] * mnz[j] < min_normal_cos);
      // Residual and Jacobian in units of the reading's own noise, relative to a reading at 1 m.
      const float zq = vz[j] - 0.4f;
      const float scale = noise_sigma_quadratic > 0.f
                              ? (noise_sigma0_m + noise_sigma_quadratic * 0.36f) /
                                    (noise_sigma0_m + noise_sigma_quadratic * zq * zq)
                              : 1.f;
      r[j] = paired ? mnx[j] * dx + mny[j] * dy + mnz[j] * dz : 0.f;
      const float abs_r = scale * fabsf(r[j]);
      robust[j] = paired ? (abs_r <= huber_m ? 1.f : huber_m / maxFloat(abs_r, huber_m)) : 0.f;
      weight[j] = robust[j] * (noise_weight_power == 2 ? scale * scale : scale);
      // d r / d xi for xi = (omega, t) applied on the left: [v x n, n]; zero where unpaired, so
      // that the products stay finite.
      J[0][j] = paired ? wy[j] * mnz[j] - wz[j] * mny[j] : 0.f;
      J[1][j] = paired ? wz[j] * mnx[j] - wx[j] * mnz[j] : 0.f;
      J[2][j] = paired ? wx[j] * mny[j] - wy[j] * mnx[j] : 0.f;
      J[3][j] = paired ? mnx[j] : 0.f;
      J[4][j] = paired ? mny[j] : 0.f;
      J[5][j] = paired ? mnz[j] : 0.f;
      row[normal_row::kInliers][j] = paired ? 1.f : 0.f;
      row[normal_row::kMeasured][j] = measured[j] ? 1.f : 0.f;
      row[normal_row::kCovered][j] = found[j] & !((mnx[j] == 0.f) & (mny[j] == 0.f) & (mnz[j] == 0.f)) ? 1.f : 0.f;
    }
    packNormalRows<L>(row, J, r, weight);
    // The statistics stay in metres, whatever the noise scaling.
    for (int j = 0; j < L; ++j) row[normal_row::kSquaredError][j] = robust[j] * r[j] * r[j];
    return true;
  }
};

// How much the model's normals scatter where its surface is smooth: the mean of |n - n'|^2 / 4
// between a prediction pixel's normal and the one kStep pixels to its right (every kStep-th
// pixel in x and y), each pair capped at kCap so that the few pairs across an edge weigh little.
// For normals with independent noise of variance s^2 per axis across the surface, that is s^2:
// what the noise alone gives a direction the surface leaves free (a wall's sliding direction has
// the share s^2 of the point-to-plane constraint; fusion/tracking.cpp solveIncrement). row[0]:
// the capped sum, row[1]: the pairs.
struct ModelNormalScatterKernel {
  static constexpr int kStep = 2;
  static constexpr float kCap = 0.05f;  // |n - n'|^2 of 13 degrees
  ImageView<const Vec3f> model_normal;

  VF_HD int count() const { return (model_normal.width / kStep) * (model_normal.height / kStep); }
  VF_HD bool operator()(int item, float* row) const {
    const int columns = model_normal.width / kStep;
    const int x = (item % columns) * kStep, y = (item / columns) * kStep;
    if (x + kStep >= model_normal.width) return false;
    const Vec3f a = model_normal(x, y), b = model_normal(x + kStep, y);
    if ((a.x == 0.f && a.y == 0.f && a.z == 0.f) || (b.x == 0.f && b.y == 0.f && b.z == 0.f)) return false;
    const float dx = a.x - b.x, dy = a.y - b.y, dz = a.z - b.z;
    const float d2 = dx * dx + dy * dy + dz * dz;
    row[0] = d2 < kCap ? d2 : kCap;
    row[1] = 1.f;
    return true;
  }
};

}  // namespace vf
