#include "io/trajectory_metrics.h"

#include <Eigen/SVD>
#include <algorithm>
#include <cmath>
#include <cstdio>
#include <initializer_list>
#include <numeric>
#include <queue>
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

// A statistic that is not finite is no result: a position out of range got past its check.
void requireFinite(std::initializer_list<double> values, const char* what) {
  for (const double v : values)
    if (!std::isfinite(v)) throw Error(std::string(what) + " is not finite: the positions are too large to compare");
}

std::string seconds(double s) {
  char buf[32];
  std::snprintf(buf, sizeof buf, "%g s", s);
  return buf;
}

}  // namespace

// associate.py takes every pair within the tolerance as a candidate and matches them greedily,
// smallest difference first (ties by a index, then b index). Listing the candidates took memory
// quadratic in dense timestamps (8,000 poses 1 us apart: 64 million pairs, 1.5 GB). The same
// matches come from neighbours alone: the closest unmatched pair has no unmatched timestamp
// strictly between its two, so it is adjacent in the merged order of what is left. Equal
// timestamps are matched first (difference 0, in index order); after that a value holds
// unmatched timestamps of one list only, and each value stands as one group whose smallest
// unmatched index is the candidate. A heap of adjacent groups gives n log n.
std::vector<std::pair<int, int>> associateTimestamps(const std::vector<double>& a, const std::vector<double>& b,
                                                     double max_difference_s, double offset_s) {
  std::vector<std::pair<int, int>> matches;
  if (!(max_difference_s > 0)) return matches;  // no difference is below it
  // Every timestamp by value (b shifted as the script shifts it), a's before b's, then by index.
  struct Item {
    double t;
    int list;  // 0: a, 1: b
    int index;
  };
  std::vector<Item> items;
  items.reserve(a.size() + b.size());
  // A timestamp that is not finite is within no difference of any other (NaN or inf - inf).
  for (int i = 0; i < int(a.size()); ++i)
    if (std::isfinite(a[size_t(i)])) items.push_back({a[size_t(i)], 0, i});
  for (int j = 0; j < int(b.size()); ++j)
    if (std::isfinite(b[size_t(j)] + offset_s)) items.push_back({b[size_t(j)] + offset_s, 1, j});
  std::sort(items.begin(), items.end(), [](const Item& x, const Item& y) {
    return std::tie(x.t, x.list, x.index) < std::tie(y.t, y.list, y.index);
  });

  // Groups of equal value: equal a's and b's pair off in index order (difference 0); what is left
  // of a value is of one list, kept as a queue of indices, smallest first.
  struct Group {
    double t;
    int list;
    std::vector<int> indices;  // ascending
    size_t head = 0;
    int prev = -1, next = -1;  // neighbouring groups with unmatched timestamps
    bool empty() const { return head == indices.size(); }
  };
  std::vector<Group> groups;
  for (size_t k = 0; k < items.size();) {
    size_t end = k;
    std::vector<int> in_a, in_b;
    while (end < items.size() && items[end].t == items[k].t) {
      (items[end].list == 0 ? in_a : in_b).push_back(items[end].index);
      ++end;
    }
    const size_t pairs = std::min(in_a.size(), in_b.size());
    for (size_t p = 0; p < pairs; ++p) matches.emplace_back(in_a[p], in_b[p]);
    if (in_a.size() != in_b.size()) {
      const bool a_left = in_a.size() > in_b.size();
      std::vector<int>& left = a_left ? in_a : in_b;
      groups.push_back({items[k].t, a_left ? 0 : 1, std::vector<int>(left.begin() + long(pairs), left.end())});
    }
    k = end;
  }
  for (int g = 0; g < int(groups.size()); ++g) {
    groups[size_t(g)].prev = g - 1;
    groups[size_t(g)].next = g + 1 < int(groups.size()) ? g + 1 : -1;
  }

  // Candidates between neighbouring groups of different lists, smallest (difference, a, b) on top.
  // An entry is stale once either group moved on (the indices it names are no longer the heads).
  struct Candidate {
    double diff;
    int i, j;          // indices into a and b
    int group_a, group_b;
    bool operator>(const Candidate& o) const { return std::tie(diff, i, j) > std::tie(o.diff, o.i, o.j); }
  };
  std::priority_queue<Candidate, std::vector<Candidate>, std::greater<Candidate>> heap;
  const auto offer = [&](int left, int right) {
    if (left < 0 || right < 0) return;
    const Group &l = groups[size_t(left)], &r = groups[size_t(right)];
    if (l.list == r.list || l.empty() || r.empty()) return;
    const Group& ga = l.list == 0 ? l : r;
    const Group& gb = l.list == 0 ? r : l;
    const double diff = std::abs(ga.t - gb.t);  // as the script: |a - (b + offset)|
    if (diff < max_difference_s)
      heap.push({diff, ga.indices[ga.head], gb.indices[gb.head], l.list == 0 ? left : right, l.list == 0 ? right : left});
  };
  for (int g = 0; g + 1 < int(groups.size()); ++g) offer(g, g + 1);
  // A group that ran out leaves the list, and its neighbours become adjacent.
  const auto advance = [&](int g) {
    Group& group = groups[size_t(g)];
    ++group.head;
    if (!group.empty()) {
      offer(group.prev, g);
      offer(g, group.next);
      return;
    }
    if (group.prev >= 0) groups[size_t(group.prev)].next = group.next;
    if (group.next >= 0) groups[size_t(group.next)].prev = group.prev;
    offer(group.prev, group.next);
  };
  while (!heap.empty()) {
    const Candidate c = heap.top();
    heap.pop();
    const Group &ga = groups[size_t(c.group_a)], &gb = groups[size_t(c.group_b)];
    if (ga.empty() || gb.empty() || ga.indices[ga.head] != c.i || gb.indices[gb.head] != c.j) continue;
    if (ga.next != c.group_b && ga.prev != c.group_b) continue;  // no longer neighbours
    matches.emplace_back(c.i, c.j);
    advance(c.group_a);
    advance(c.group_b);
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
  requireFinite({s.rmse, s.mean, s.median, s.max}, "the ATE");
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

void requirePlausiblePositions(const Trajectory& trajectory, const std::string& source) {
  for (size_t i = 0; i < trajectory.size(); ++i) {
    const Eigen::Vector3d t = trajectory[i].T_world_cam.translation();
    if (t.allFinite() && t.cwiseAbs().maxCoeff() <= kMaxPlausiblePosition_m) continue;
    char text[160];
    std::snprintf(text, sizeof text, "pose %zu (t = %.6f) is at (%g, %g, %g) m, not a camera position (beyond %g m)",
                  i + 1, trajectory[i].timestamp, t.x(), t.y(), t.z(), kMaxPlausiblePosition_m);
    throw Error(source + ": " + text);
  }
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
  requireFinite({t.rmse, t.mean, t.median, t.max, r.rmse, r.mean, r.median, r.max}, "the RPE");
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
