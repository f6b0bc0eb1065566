#include "io/trajectory_metrics.h"

#include <Eigen/SVD>
#include <algorithm>
#include <cmath>
#include <cstdio>
#include <numeric>
#include <string>
#include <tuple>

#include "core/error.h"

namespace vf {
namespace {

std::vector<double> timestamps(const Trajectory& t) {
  std::vector<double> out;
  out.reserve(t.size());
  for (const StampedPose& p : t) out.push_back(p.timestamp);
  return out;
}

Trajectory sortedByTime(Trajectory t) {
  std::stable_sort(t.begin(), t.end(),
                   [](const StampedPose& a, const StampedPose& b) { return a.timestamp < b.timestamp; });
  return t;
}

// Index of the element of sorted `ts` nearest to t (ts non-empty).
int nearestIndex(const std::vector<double>& ts, double t) {
  const auto it = std::lower_bound(ts.begin(), ts.end(), t);
  if (it == ts.begin()) return 0;
  if (it == ts.end()) return int(ts.size()) - 1;
  const int hi = int(it - ts.begin());
  return (t - ts[hi - 1] <= ts[hi] - t) ? hi - 1 : hi;
}

struct Stats {
  double rmse = 0, mean = 0, median = 0, std = 0, min = 0, max = 0;
};
Stats statistics(std::vector<double> v) {
  Stats s;
  const double n = double(v.size());
  double sum = 0, sum_sq = 0;
  for (double x : v) sum += x, sum_sq += x * x;
  s.mean = sum / n;
  s.rmse = std::sqrt(sum_sq / n);
  s.std = std::sqrt(std::max(0.0, sum_sq / n - s.mean * s.mean));  // population std, as numpy.std
  std::sort(v.begin(), v.end());
  const size_t m = v.size() / 2;
  s.median = v.size() % 2 ? v[m] : 0.5 * (v[m - 1] + v[m]);  // numpy.median
  s.min = v.front();
  s.max = v.back();
  return s;
}

constexpr double kRadToDeg = 180.0 / M_PI;

std::string seconds(double s) {
  char buf[32];
  std::snprintf(buf, sizeof buf, "%g s", s);
  return buf;
}

}  // namespace

std::vector<std::pair<int, int>> associateTimestamps(const std::vector<double>& a, const std::vector<double>& b,
                                                     double max_difference_s, double offset_s) {
  // Candidates come from a window search in sorted b, not all |a| x |b| pairs; the greedy
  // choice afterwards is the script's. Ties break by (a index, b index) for determinism.
  std::vector<int> b_order(b.size());
  std::iota(b_order.begin(), b_order.end(), 0);
  std::sort(b_order.begin(), b_order.end(), [&](int i, int j) { return b[i] < b[j]; });
  std::vector<double> b_sorted;
  for (int j : b_order) b_sorted.push_back(b[j] + offset_s);

  std::vector<std::tuple<double, int, int>> candidates;
  for (int i = 0; i < int(a.size()); ++i) {
    auto it = std::lower_bound(b_sorted.begin(), b_sorted.end(), a[i] - max_difference_s);
    for (; it != b_sorted.end() && *it <= a[i] + max_difference_s; ++it) {
      const double diff = std::abs(a[i] - *it);
      if (diff < max_difference_s) candidates.emplace_back(diff, i, b_order[size_t(it - b_sorted.begin())]);
    }
  }
  std::sort(candidates.begin(), candidates.end());
  std::vector<char> a_used(a.size(), 0), b_used(b.size(), 0);
  std::vector<std::pair<int, int>> matches;
  for (const auto& [diff, i, j] : candidates) {
    if (a_used[i] || b_used[j]) continue;
    a_used[i] = b_used[j] = 1;
    matches.emplace_back(i, j);
  }
  std::sort(matches.begin(), matches.end());
  return matches;
}

std::optional<Pose> poseNearTimestamp(const Trajectory& trajectory, double t_s, double max_difference_s) {
  const StampedPose* best = nullptr;
  for (const StampedPose& p : trajectory)
    if (!best || std::abs(p.timestamp - t_s) < std::abs(best->timestamp - t_s)) best = &p;
  if (!best || std::abs(best->timestamp - t_s) > max_difference_s) return std::nullopt;
  return best->T_world_cam;
}

AteResult computeAte(const Trajectory& estimate, const Trajectory& ground_truth, double max_difference_s) {
  const auto matches = associateTimestamps(timestamps(ground_truth), timestamps(estimate), max_difference_s);
  const int n = int(matches.size());
  if (n < 3)
    throw Error("ATE needs at least 3 estimated poses within " + seconds(max_difference_s) +
                " of a ground-truth pose, found " + std::to_string(n) +
                " (do the two files use the same clock?)");
  Eigen::Matrix3Xd est(3, n), gt(3, n);
  for (int k = 0; k < n; ++k) {
    gt.col(k) = ground_truth[size_t(matches[k].first)].T_world_cam.translation();
    est.col(k) = estimate[size_t(matches[k].second)].T_world_cam.translation();
  }
  // Kabsch / Horn: R maximises trace(R^T H) for H = sum (gt - gt_mean)(est - est_mean)^T.
  const Eigen::Vector3d est_mean = est.rowwise().mean(), gt_mean = gt.rowwise().mean();
  const Eigen::Matrix3d H = (gt.colwise() - gt_mean) * (est.colwise() - est_mean).transpose();
  Eigen::JacobiSVD<Eigen::Matrix3d> svd(H, Eigen::ComputeFullU | Eigen::ComputeFullV);
  Eigen::Matrix3d S = Eigen::Matrix3d::Identity();
  if (svd.matrixU().determinant() * svd.matrixV().determinant() < 0) S(2, 2) = -1;  // no reflection
  const Eigen::Matrix3d R = svd.matrixU() * S * svd.matrixV().transpose();
  const Eigen::Vector3d t = gt_mean - R * est_mean;

  std::vector<double> residual_m(static_cast<size_t>(n));
  for (int k = 0; k < n; ++k) residual_m[size_t(k)] = (R * est.col(k) + t - gt.col(k)).norm();
  const Stats s = statistics(residual_m);
  AteResult r;
  r.pairs = n;
  r.rmse_m = s.rmse;
  r.mean_m = s.mean;
  r.median_m = s.median;
  r.std_m = s.std;
  r.min_m = s.min;
  r.max_m = s.max;
  r.T_gt_est.linear() = R;
  r.T_gt_est.translation() = t;
  return r;
}

void requireDistinctTimestamps(const Trajectory& trajectory, const std::string& source) {
  std::vector<double> t = timestamps(trajectory);
  std::sort(t.begin(), t.end());
  const auto twin = std::adjacent_find(t.begin(), t.end());
  if (twin != t.end()) {
    char when[64];
    std::snprintf(when, sizeof when, "%.6f", *twin);
    throw Error(source + ": two poses have the timestamp " + when + "; a trajectory needs one pose per time");
  }
}

RpeResult computeRpe(const Trajectory& estimate_in, const Trajectory& ground_truth_in, int delta_frames) {
  if (delta_frames < 1) throw Error("RPE --delta must be at least 1 frame, got " + std::to_string(delta_frames));
  const Trajectory est = sortedByTime(estimate_in), gt = sortedByTime(ground_truth_in);
  if (gt.size() < 2) throw Error("RPE needs a ground truth with at least 2 poses");
  const std::vector<double> gt_t = timestamps(gt);
  std::vector<double> gaps;
  for (size_t i = 1; i < gt_t.size(); ++i) gaps.push_back(gt_t[i] - gt_t[i - 1]);
  std::nth_element(gaps.begin(), gaps.begin() + gaps.size() / 2, gaps.end());
  const double max_difference_s = 2 * gaps[gaps.size() / 2];  // evaluate_rpe.py's tolerance

  std::vector<double> trans_m, rot_deg;
  for (size_t i = 0; i + size_t(delta_frames) < est.size(); ++i) {
    const size_t j = i + size_t(delta_frames);
    const int gi = nearestIndex(gt_t, est[i].timestamp), gj = nearestIndex(gt_t, est[j].timestamp);
    if (std::abs(gt_t[size_t(gi)] - est[i].timestamp) > max_difference_s ||
        std::abs(gt_t[size_t(gj)] - est[j].timestamp) > max_difference_s)
      continue;
    const Pose d_est = est[i].T_world_cam.inverse() * est[j].T_world_cam;
    const Pose d_gt = gt[size_t(gi)].T_world_cam.inverse() * gt[size_t(gj)].T_world_cam;
    const Pose error = d_est * d_gt.inverse();  // ominus(ominus(E_j, E_i), ominus(G_j, G_i)) of the script
    trans_m.push_back(error.translation().norm());
    const double c = std::clamp((error.linear().trace() - 1.0) / 2.0, -1.0, 1.0);
    rot_deg.push_back(std::acos(c) * kRadToDeg);
  }
  if (trans_m.size() < 3)
    throw Error("RPE needs at least 3 frame pairs " + std::to_string(delta_frames) +
                " frame(s) apart with ground truth, found " + std::to_string(trans_m.size()));
  const Stats t = statistics(trans_m), r = statistics(rot_deg);
  RpeResult out;
  out.pairs = int(trans_m.size());
  out.delta_frames = delta_frames;
  out.trans_rmse_m = t.rmse;
  out.trans_mean_m = t.mean;
  out.trans_median_m = t.median;
  out.trans_max_m = t.max;
  out.rot_rmse_deg = r.rmse;
  out.rot_mean_deg = r.mean;
  out.rot_median_deg = r.median;
  out.rot_max_deg = r.max;
  return out;
}

}  // namespace vf
