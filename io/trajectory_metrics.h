#pragma once
// Trajectory accuracy as TUM RGB-D's evaluate_ate.py and evaluate_rpe.py compute it (Sturm et al.
// 2012), so numbers can be compared with published tables. Also the timestamp association that
// TUM's associate.py does, shared with the dataset reader.
#include <optional>
#include <utility>
#include <vector>

#include "core/error.h"
#include "core/pose.h"

namespace vf {

// TUM's association tolerance (associate.py --max_difference default).
constexpr double kTumMaxTimeDifference_s = 0.02;

// associate.py: every pair (i, j) with |a[i] - (b[j] + offset_s)| < max_difference_s is a
// candidate; candidates are taken greedily by smallest difference, each element used at most
// once. Returns (index into a, index into b) sorted by index into a.
std::vector<std::pair<int, int>> associateTimestamps(const std::vector<double>& a,
                                                     const std::vector<double>& b,
                                                     double max_difference_s = kTumMaxTimeDifference_s,
                                                     double offset_s = 0);

// Pose whose timestamp is nearest to t within max_difference_s, else nullopt (what a frame
// looks up in a ground truth recorded at a different rate).
std::optional<Pose> poseNearTimestamp(const Trajectory& trajectory, double t_s,
                                      double max_difference_s = kTumMaxTimeDifference_s);

// Absolute trajectory error: estimate aligned to ground truth by the rigid motion (no scale)
// minimising the squared position residuals (Horn 1987 / Umeyama 1991), then statistics of
// the residual lengths, in metres.
struct AteResult {
  int pairs = 0;
  double rmse_m = 0, mean_m = 0, median_m = 0, std_m = 0, min_m = 0, max_m = 0;
  Pose T_gt_est = Pose::Identity();  // the alignment: ground truth ~ T_gt_est * estimate
};
// Throws vf::Error when fewer than 3 poses associate (the alignment is then undetermined), and
// when the result is not finite (positions beyond kMaxPlausiblePosition_m).
// Throws vf::Error naming `source` and the time when two poses share a timestamp: TUM's tools
// would pair either with the ground truth, and RPE's steps would be zero or doubled.
void requireDistinctTimestamps(const Trajectory& trajectory, const std::string& source);

// Farther from its origin than this (a million kilometres) a position is no camera's: squares
// and sums of such numbers overflow, and "inf cm" was printed as a result.
constexpr double kMaxPlausiblePosition_m = 1e9;
// Throws vf::Error naming `source`, the pose and its timestamp when a position is not finite or
// lies farther than kMaxPlausiblePosition_m from the origin.
void requirePlausiblePositions(const Trajectory& trajectory, const std::string& source);

AteResult computeAte(const Trajectory& estimate, const Trajectory& ground_truth,
                     double max_difference_s = kTumMaxTimeDifference_s);

// Relative pose error over a fixed frame distance `delta_frames` (evaluate_rpe.py --fixed_delta
// --delta_unit f): for estimate poses i and i+delta, E = (E_i^-1 E_j) (G_i^-1 G_j)^-1 with G the
// ground-truth poses nearest in time (within twice the median ground-truth interval, as the
// script). Translational error |t(E)| in metres, rotational error angle(R(E)) in degrees.
struct RpeResult {
  int pairs = 0;
  int delta_frames = 1;
  double trans_rmse_m = 0, trans_mean_m = 0, trans_median_m = 0, trans_max_m = 0;
  double rot_rmse_deg = 0, rot_mean_deg = 0, rot_median_deg = 0, rot_max_deg = 0;
};
// Throws vf::Error when fewer than 3 pairs remain, delta_frames < 1 or the result is not finite.
RpeResult computeRpe(const Trajectory& estimate, const Trajectory& ground_truth, int delta_frames = 1);

}  // namespace vf
