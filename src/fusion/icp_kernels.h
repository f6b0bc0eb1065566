#pragma once
// Sensor pose estimation (KinectFusion section 3.5): projective data association against the
// raycast prediction and the point-to-plane error, eq. (16), linearised around the current
// estimate. Each pixel contributes one row of the 6x6 normal equations.
#include "core/image.h"
#include "core/intrinsics.h"
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

  int stride_px = 1;  // use every stride-th measured pixel in x and y

  // Number of work items for the reduction.
  VF_HD int count() const { return stridedPixelCount(vertex_cam.width, vertex_cam.height, stride_px); }

  VF_HD bool operator()(int item, float* row) const {
    const int i = stridedPixel(item, vertex_cam.width, stride_px);
    const Vec3f v_cam = vertex_cam[i];
    if (v_cam.z <= 0.f) return false;
    const Vec3f n_cam = normal_cam[i];
    if (n_cam.x == 0.f && n_cam.y == 0.f && n_cam.z == 0.f) return false;
    for (int k = 0; k < normal_row::kSize; ++k) row[k] = 0.f;
    row[normal_row::kMeasured] = 1.f;  // a usable measurement, matched or not
    correspond(v_cam, n_cam, row);
    return true;
  }

  // Fills the row's equations and inlier count when the measurement finds a model partner that passes both rejections.
  VF_HD void correspond(Vec3f v_cam, Vec3f n_cam, float* row) const {
    const Vec3f v = T_world_cam * v_cam;
    const Vec3f n = T_world_cam.rotate(n_cam);
    float u, w;
    if (!model_intrinsics.project(T_model_world * v, u, w)) return;
    if (!(u >= -0.5f && w >= -0.5f && u < float(model_vertex.width) - 0.5f && w < float(model_vertex.height) - 0.5f))
      return;
    const int px = int(floorf(u + 0.5f)), py = int(floorf(w + 0.5f));
    if (!model_vertex.inside(px, py)) return;
    const Vec3f mv = model_vertex(px, py);
    const Vec3f mn = model_normal(px, py);
    if (mn.x == 0.f && mn.y == 0.f && mn.z == 0.f) return;
    const Vec3f diff = v - mv;
    if (dot(diff, diff) > max_distance_m * max_distance_m) return;
    if (dot(n, mn) < min_normal_cos) return;
    const float r = dot(mn, diff);
    const float abs_r = fabsf(r);
    const float weight = abs_r <= huber_m ? 1.f : huber_m / abs_r;
    // d r / d xi for xi = (omega, t) applied on the left: [v x n, n]
    const Vec3f a = cross(v, mn);
    const float J[6] = {a.x, a.y, a.z, mn.x, mn.y, mn.z};
    packNormalRow(row, J, r, weight);
    row[normal_row::kInliers] = 1.f;
  }
};

}  // namespace vf
