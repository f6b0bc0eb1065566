// Pipeline::solveIcp and judgeTracking: multi-scale frame-to-model ICP (KinectFusion section
// 3.5) with an optional photometric term, then the decision whether to trust the result.
#include <Eigen/Cholesky>
#include <algorithm>
#include <array>
#include <cmath>
#include <cstdio>

#include "fusion/icp_kernels.h"
#include "fusion/normal_equations.h"
#include "fusion/parallel.h"
#include "fusion/photometric_kernels.h"
#include "fusion/pipeline.h"
#include "fusion/pipeline_buffers.h"

namespace vf {
namespace {

using RowSums = std::array<double, normal_row::kSize>;

// Solves the summed normal equations for the increment xi = (omega, v); false when singular.
bool solveIncrement(const RowSums& sums, Eigen::Matrix<double, 6, 1>& xi) {
  Eigen::Matrix<double, 6, 6> A;
  Eigen::Matrix<double, 6, 1> rhs;
  int k = normal_row::kHessian;
  for (int r = 0; r < 6; ++r)
    for (int c = r; c < 6; ++c) A(r, c) = A(c, r) = sums[size_t(k++)];
  for (int r = 0; r < 6; ++r) rhs(r) = -sums[size_t(normal_row::kGradient + r)];
  xi = A.ldlt().solve(rhs);
  return xi.allFinite();
}

// Left-multiplied increment exp(xi) for xi = (omega, v): rotation by the axis-angle omega and
// translation v.
Pose twistToPose(const Eigen::Matrix<double, 6, 1>& xi) {
  Pose delta = Pose::Identity();
  const Eigen::Vector3d omega = xi.head<3>();
  const double angle = omega.norm();
  if (angle > 1e-12) delta.linear() = Eigen::AngleAxisd(angle, omega / angle).toRotationMatrix();
  delta.translation() = xi.tail<3>();
  return delta;
}

double rotationDeg(const Pose& delta) { return Eigen::AngleAxisd(delta.linear()).angle() * 180.0 / M_PI; }

}  // namespace

struct Pipeline::IcpSolution {
  Pose T_world_cam;
  // Geometric sums at the finest level, for the tracking-loss statistics. They describe the pose
  // before the last finest-level iteration's (converged, tiny) update, which saves a pass.
  RowSums finest_sums{};
};

Pipeline::IcpSolution Pipeline::solveIcp(const Pose& initial_guess) {
  Buffers& b = *buffers_;
  const IcpParams& p = params_.icp;
  IcpSolution solution;
  Pose& T = solution.T_world_cam;
  T = initial_guess;
  const Rigid3f T_model_world = toRigid3f(state_.T_world_model.inverse());
  // The prediction exists from params_.raycast.prediction_level down; finer measured levels
  // associate against it (projective association only needs the model's camera).
  auto modelLevel = [&](int l) { return std::max(l, params_.raycast.prediction_level); };
  auto icpAtLevel = [&](int l) {
    IcpKernel icp;
    icp.vertex_cam = constView(b.vertex[l]);
    icp.normal_cam = constView(b.normal[l]);
    icp.model_vertex = constView(b.model_vertex[modelLevel(l)]);
    icp.model_normal = constView(b.model_normal[modelLevel(l)]);
    icp.model_intrinsics = intrinsics_.atLevel(modelLevel(l));
    icp.T_model_world = T_model_world;
    icp.max_distance_m = p.max_distance_m;
    icp.min_normal_cos = std::cos(p.max_normal_angle_deg * float(M_PI) / 180.f);
    icp.huber_m = p.huber_m;
    icp.stride_px = p.stride_px[size_t(l)];
    return icp;
  };
  bool have_finest_sums = false;
  for (int l = kPyramidLevels - 1; l >= 0; --l) {
    IcpKernel icp = icpAtLevel(l);
    PhotometricKernel photo;
    const bool use_photometric = photometricActive() && l >= p.photometric_finest_level;
    if (use_photometric) {
      photo.model_vertex = constView(b.model_vertex[modelLevel(l)]);
      photo.model_normal = constView(b.model_normal[modelLevel(l)]);
      photo.model_intensity = constView(b.model_intensity[modelLevel(l)]);
      photo.intensity = constView(b.intensity[l]);
      photo.gradient = constView(b.intensity_gradient[l]);
      photo.depth = constView(b.depth[l]);
      photo.intrinsics = intrinsics_.atLevel(l);
      photo.weight = p.photometric_weight;
      photo.huber = p.photometric_huber;
      // The model pixels at the spacing of the measured ones (in level-0 pixels): the coarser
      // prediction is sampled less densely.
      photo.stride_px = std::max(1, (p.stride_px[size_t(l)] << l) >> modelLevel(l));
    }
    // Converged once an update moves a point 1 m away by less than a small share of this level's
    // pixel: further iterations cannot change which pixels correspond.
    const double converged = double(p.convergence_px[size_t(l)]) * double(1 << l) / double(intrinsics_.fx);
    for (int it = 0; it < p.iterations[size_t(l)]; ++it) {
      icp.T_world_cam = toRigid3f(T);
      RowSums sums = parallelReduce<normal_row::kSize>(device_, icp.count(), icp);
      if (l == 0) {
        solution.finest_sums = sums;
        have_finest_sums = true;
      }
      if (sums[normal_row::kInliers] < 6) break;
      if (use_photometric) {
        photo.T_world_cam = icp.T_world_cam;
        photo.T_cam_world = toRigid3f(T.inverse());
        const RowSums photometric = parallelReduce<normal_row::kSize>(device_, photo.count(), photo);
        for (int k = normal_row::kHessian; k < normal_row::kSquaredError; ++k) sums[size_t(k)] += photometric[size_t(k)];
      }
      Eigen::Matrix<double, 6, 1> xi;
      if (!solveIncrement(sums, xi)) break;
      T = twistToPose(xi) * T;
      if (xi.head<3>().norm() < converged && xi.tail<3>().norm() < converged) break;
    }
  }
  if (!have_finest_sums) {  // no finest-level iteration ran: measure the final pose there
    IcpKernel icp = icpAtLevel(0);
    icp.T_world_cam = toRigid3f(T);
    solution.finest_sums = parallelReduce<normal_row::kSize>(device_, icp.count(), icp);
  }
  return solution;
}

FrameResult Pipeline::track(const Pose& initial_guess) { return judgeTracking(solveIcp(initial_guess)); }

FrameResult Pipeline::judgeTracking(const IcpSolution& solution) const {
  const IcpParams& p = params_.icp;
  const RowSums& sums = solution.finest_sums;
  const Pose& T = solution.T_world_cam;
  FrameResult result;
  const double inliers = sums[normal_row::kInliers];
  result.icp_inliers = int(inliers);
  result.icp_rmse_m = inliers > 0 ? float(std::sqrt(sums[normal_row::kSquaredError] / inliers)) : 0.f;
  result.T_world_cam = T;
  // The fraction is relative to the measured pixels that have a normal (what ICP can use).
  const int measured = int(sums[normal_row::kMeasured]);
  result.icp_inlier_fraction = measured > 0 ? float(result.icp_inliers) / float(measured) : 0.f;
  const Pose motion = state_.T_world_cam.inverse() * T;
  char why[160] = "";
  if (measured == 0) std::snprintf(why, sizeof(why), "no valid depth");
  else if (!T.matrix().allFinite()) std::snprintf(why, sizeof(why), "ICP diverged");
  else if (result.icp_inlier_fraction < p.min_inlier_fraction)
    std::snprintf(why, sizeof(why), "only %.0f%% of pixels matched the model (min %.0f%%)",
                  100.f * result.icp_inlier_fraction, 100.f * p.min_inlier_fraction);
  else if (result.icp_rmse_m > p.max_rmse_m)
    std::snprintf(why, sizeof(why), "residual %.1f mm above %.1f mm", 1e3f * result.icp_rmse_m, 1e3f * p.max_rmse_m);
  else if (motion.translation().norm() > p.max_translation_m)
    std::snprintf(why, sizeof(why), "moved %.2f m in one frame", motion.translation().norm());
  else if (rotationDeg(motion) > p.max_rotation_deg)
    std::snprintf(why, sizeof(why), "turned %.1f deg in one frame", rotationDeg(motion));
  result.lost_reason = why;
  result.tracked = result.lost_reason.empty();
  return result;
}

}  // namespace vf
