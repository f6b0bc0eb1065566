#include "io/trajectory_alignment.h"

#include <Eigen/SVD>
#include <cmath>
#include <cstdio>

#include "core/error.h"
#include "io/trajectory_metrics.h"

namespace vf {
namespace {

// RMS distance of the associated estimate positions from their best-fit line.
double lateralSpread(const Trajectory& estimate, const Trajectory& ground_truth) {
  std::vector<double> a, b;
  for (const StampedPose& p : estimate) a.push_back(p.timestamp);
  for (const StampedPose& p : ground_truth) b.push_back(p.timestamp);
  const auto pairs = associateTimestamps(a, b);
  if (pairs.size() < 3) return 0;
  Eigen::Vector3d mean = Eigen::Vector3d::Zero();
  for (const auto& pair : pairs) mean += estimate[size_t(pair.first)].T_world_cam.translation();
  mean /= double(pairs.size());
  // The squared singular values of the centred 3xN positions are the eigenvalues (and, the
  // matrix being symmetric, the singular values) of their 3x3 scatter: a fixed-size SVD, which
  // compiles in a fraction of the time of the 3xN one.
  Eigen::Matrix3d scatter = Eigen::Matrix3d::Zero();
  for (const auto& pair : pairs) {
    const Eigen::Vector3d d = estimate[size_t(pair.first)].T_world_cam.translation() - mean;
    scatter += d * d.transpose();
  }
  const Eigen::JacobiSVD<Eigen::Matrix3d> svd(scatter);
  return std::sqrt(svd.singularValues()(1) / double(pairs.size()));
}

std::string metres(double v) {
  char text[32];
  std::snprintf(text, sizeof text, "%.2f cm", v * 100);
  return text;
}

}  // namespace

AlignmentMethod parseAlignmentMethod(const std::string& text) {
  if (text == "auto") return AlignmentMethod::Auto;
  if (text == "ate") return AlignmentMethod::Ate;
  if (text == "first") return AlignmentMethod::FirstPose;
  if (text == "none") return AlignmentMethod::None;
  throw Error("alignment '" + text + "': expected auto, ate, first or none");
}

TrajectoryAlignment alignTrajectory(const Trajectory& estimate, const Trajectory& ground_truth,
                                    AlignmentMethod method) {
  TrajectoryAlignment out;
  if (method == AlignmentMethod::None) {
    out.description = "none (the mesh is taken to be in the reference's frame)";
    return out;
  }
  std::string why;
  if (method == AlignmentMethod::Auto) {
    const double spread = lateralSpread(estimate, ground_truth);
    method = spread >= kMinLateralSpread_m ? AlignmentMethod::Ate : AlignmentMethod::FirstPose;
    if (method == AlignmentMethod::FirstPose)
      why = "; the camera positions lie within " + metres(spread) + " of a line, too little to fix a rotation";
  }
  if (method == AlignmentMethod::Ate) {
    const AteResult ate = computeAte(estimate, ground_truth);
    out.T_gt_est = ate.T_gt_est;
    out.method = method;
    out.pairs = ate.pairs;
    out.description = "the ATE's rigid alignment of the trajectory to the ground truth (" + std::to_string(ate.pairs) +
                      " poses, residual rmse " + metres(ate.rmse_m) + ")";
    return out;
  }
  for (const StampedPose& e : estimate) {
    const std::optional<Pose> g = poseNearTimestamp(ground_truth, e.timestamp);
    if (!g) continue;
    out.T_gt_est = *g * e.T_world_cam.inverse();
    out.method = AlignmentMethod::FirstPose;
    out.pairs = 1;
    char t[32];
    std::snprintf(t, sizeof t, "%.6f", e.timestamp);
    out.description = std::string("the first pose's correspondence (t = ") + t + " s onto its ground-truth pose" + why + ")";
    return out;
  }
  throw Error("the trajectory and the ground truth share no timestamp (within 0.02 s)");
}

}  // namespace vf
