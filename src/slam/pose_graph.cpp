#include "slam/pose_graph.h"

#include <ceres/ceres.h>
#include <ceres/rotation.h>

#include <Eigen/Cholesky>
#include <Eigen/Eigenvalues>
#include <cmath>
#include <array>
#include <memory>

#include "core/error.h"

namespace vf::slam {
namespace {

// The error of one edge, (omega, v) of E = Z^-1 (T_from^-1 T_to) to first order: the rotation
// vector of E's rotation and E's translation, whitened by the square root of the information.
class RelativePoseError {
 public:
  RelativePoseError(const Pose& measured, const Eigen::Matrix<double, 6, 6>& sqrt_information)
      : q_measured_(measured.linear()), t_measured_(measured.translation()), sqrt_information_(sqrt_information) {}

  template <typename T>
  bool operator()(const T* q_from_raw, const T* t_from_raw, const T* q_to_raw, const T* t_to_raw, T* residual) const {
    const Eigen::Map<const Eigen::Quaternion<T>> q_from(q_from_raw), q_to(q_to_raw);
    const Eigen::Map<const Eigen::Matrix<T, 3, 1>> t_from(t_from_raw), t_to(t_to_raw);
    // Estimated relative pose from -> to.
    const Eigen::Quaternion<T> q_rel = q_from.conjugate() * q_to;
    const Eigen::Matrix<T, 3, 1> t_rel = q_from.conjugate() * (t_to - t_from);
    // E = Z^-1 * estimate.
    const Eigen::Quaternion<T> q_meas_inv = q_measured_.conjugate().cast<T>();
    const Eigen::Quaternion<T> q_err = q_meas_inv * q_rel;
    const Eigen::Matrix<T, 3, 1> t_err = q_meas_inv * (t_rel - t_measured_.cast<T>());
    Eigen::Matrix<T, 6, 1> e;
    T q[4] = {q_err.w(), q_err.x(), q_err.y(), q_err.z()};
    T omega[3];
    ceres::QuaternionToAngleAxis(q, omega);
    e << omega[0], omega[1], omega[2], t_err;
    Eigen::Map<Eigen::Matrix<T, 6, 1>> out(residual);
    out = sqrt_information_.cast<T>() * e;
    return true;
  }

 private:
  Eigen::Quaterniond q_measured_;
  Eigen::Vector3d t_measured_;
  Eigen::Matrix<double, 6, 6> sqrt_information_;
};

// L with L^T L = I (upper Cholesky factor), after making I symmetric positive definite.
Eigen::Matrix<double, 6, 6> sqrtInformation(const Eigen::Matrix<double, 6, 6>& information) {
  Eigen::Matrix<double, 6, 6> s = 0.5 * (information + information.transpose());
  const Eigen::SelfAdjointEigenSolver<Eigen::Matrix<double, 6, 6>> eigen(s);
  const double floor = std::max(1e-9, 1e-9 * eigen.eigenvalues().maxCoeff());
  const Eigen::Matrix<double, 6, 1> values = eigen.eigenvalues().cwiseMax(floor);
  return values.cwiseSqrt().asDiagonal() * eigen.eigenvectors().transpose();
}

Eigen::Matrix<double, 6, 1> edgeError(const PoseGraphEdge& edge, const std::vector<Pose>& poses) {
  const Pose E = edge.T_from_to.inverse() * (poses[size_t(edge.from)].inverse() * poses[size_t(edge.to)]);
  const Eigen::AngleAxisd aa(E.linear());
  Eigen::Matrix<double, 6, 1> e;
  e << aa.angle() * aa.axis(), E.translation();
  return e;
}

std::vector<Pose> solve(const std::vector<Pose>& initial, const std::vector<PoseGraphEdge>& edges,
                        const std::vector<bool>& kept, const PoseGraphParams& params) {
  const int n = int(initial.size());
  // Parameters: a unit quaternion (x, y, z, w, Eigen's order) and a translation per node.
  std::vector<std::array<double, 4>> q(static_cast<size_t>(n));
  std::vector<std::array<double, 3>> t(static_cast<size_t>(n));
  for (int i = 0; i < n; ++i) {
    const Eigen::Quaterniond r(initial[size_t(i)].linear());
    q[size_t(i)] = {r.x(), r.y(), r.z(), r.w()};
    const Eigen::Vector3d p = initial[size_t(i)].translation();
    t[size_t(i)] = {p.x(), p.y(), p.z()};
  }
  ceres::Problem problem;
  for (int i = 0; i < n; ++i) {
    problem.AddParameterBlock(q[size_t(i)].data(), 4, new ceres::EigenQuaternionManifold);
    problem.AddParameterBlock(t[size_t(i)].data(), 3);
  }
  problem.SetParameterBlockConstant(q[0].data());
  problem.SetParameterBlockConstant(t[0].data());
  for (size_t k = 0; k < edges.size(); ++k) {
    const PoseGraphEdge& e = edges[k];
    if (!kept[k]) continue;
    auto* cost = new ceres::AutoDiffCostFunction<RelativePoseError, 6, 4, 3, 4, 3>(
        new RelativePoseError(e.T_from_to, sqrtInformation(e.information)));
    ceres::LossFunction* loss = e.loop ? new ceres::CauchyLoss(params.loop_loss_scale) : nullptr;
    problem.AddResidualBlock(cost, loss, q[size_t(e.from)].data(), t[size_t(e.from)].data(), q[size_t(e.to)].data(),
                             t[size_t(e.to)].data());
  }
  ceres::Solver::Options options;
  options.linear_solver_type = ceres::SPARSE_NORMAL_CHOLESKY;
  options.max_num_iterations = 100;
  options.num_threads = 1;  // the same answer on every machine
  ceres::Solver::Summary summary;
  ceres::Solve(options, &problem, &summary);
  std::vector<Pose> poses(static_cast<size_t>(n));
  for (int i = 0; i < n; ++i) {
    const auto& r = q[size_t(i)];
    Pose p = Pose::Identity();
    p.linear() = Eigen::Quaterniond(r[3], r[0], r[1], r[2]).normalized().toRotationMatrix();
    p.translation() = Eigen::Vector3d(t[size_t(i)][0], t[size_t(i)][1], t[size_t(i)][2]);
    poses[size_t(i)] = p;
  }
  return poses;
}

}  // namespace

void PoseGraphParams::validate() const {
  if (!(loop_loss_scale > 0) || !(max_loop_chi > 0) || max_rounds < 1)
    throw Error("PoseGraphParams: loop_loss_scale and max_loop_chi must be > 0, max_rounds >= 1");
}

double edgeChi(const PoseGraphEdge& edge, const std::vector<Pose>& poses) {
  const Eigen::Matrix<double, 6, 1> e = edgeError(edge, poses);
  return std::sqrt(std::max(0.0, e.dot(0.5 * (edge.information + edge.information.transpose()) * e)));
}

PoseGraphResult optimisePoseGraph(const std::vector<Pose>& initial, const std::vector<PoseGraphEdge>& edges,
                                  const PoseGraphParams& params) {
  params.validate();
  const int n = int(initial.size());
  for (const PoseGraphEdge& e : edges)
    if (e.from < 0 || e.to < 0 || e.from >= n || e.to >= n || e.from == e.to)
      throw Error("pose graph: an edge joins node " + std::to_string(e.from) + " and " + std::to_string(e.to) + " of " +
                  std::to_string(n));
  PoseGraphResult result;
  result.poses = initial;
  result.loop_kept.assign(edges.size(), true);
  if (n < 2) return result;
  // Solves with the loops still switched on, from the odometry's poses (not from a map a wrong
  // loop bent); then switches off the worst loop that still disagrees and solves again, one loop
  // at a time (a wrong loop can pull right ones off with it).
  while (true) {
    result.poses = solve(initial, edges, result.loop_kept, params);
    ++result.rounds;
    int worst = -1;
    double worst_chi = params.max_loop_chi;
    for (size_t k = 0; k < edges.size(); ++k) {
      if (!edges[k].loop || !result.loop_kept[k]) continue;
      const double chi = edgeChi(edges[k], result.poses);
      if (chi > worst_chi) worst_chi = chi, worst = int(k);
    }
    if (worst < 0 || result.rounds >= params.max_rounds) {
      if (worst >= 0) {  // out of rounds: leave every loop that still disagrees out, and solve once more
        for (size_t k = 0; k < edges.size(); ++k)
          if (edges[k].loop && result.loop_kept[k] && edgeChi(edges[k], result.poses) > params.max_loop_chi)
            result.loop_kept[k] = false;
        result.poses = solve(initial, edges, result.loop_kept, params);
        ++result.rounds;
      }
      break;
    }
    result.loop_kept[size_t(worst)] = false;
  }
  return result;
}

}  // namespace vf::slam
