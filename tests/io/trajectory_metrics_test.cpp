#include <gtest/gtest.h>
#include <sys/resource.h>
#include <sys/wait.h>
#include <unistd.h>

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <functional>
#include <new>
#include <random>
#include <tuple>

#include "io/trajectory_io.h"
#include "io/trajectory_metrics.h"
#include "test_data.h"

namespace vf {
namespace {

constexpr double kPi = 3.14159265358979323846;

// A generic, non-planar path: positions span all three axes so the alignment is determined.
Trajectory spiral(int n, double t0 = 100.0) {
  Trajectory t;
  for (int i = 0; i < n; ++i) {
    StampedPose p;
    p.timestamp = t0 + 0.03 * i;
    const double a = 0.2 * i;
    p.T_world_cam = Eigen::Translation3d(std::cos(a), std::sin(a), 0.05 * i + 0.3 * std::sin(0.7 * a)) *
                    Eigen::AngleAxisd(0.05 * i, Eigen::Vector3d::UnitY());
    t.push_back(p);
  }
  return t;
}

Pose someRigidMotion() {
  return Pose(Eigen::Translation3d(3.0, -2.0, 0.5) *
              Eigen::AngleAxisd(1.1, Eigen::Vector3d(0.2, -0.5, 0.8).normalized()));
}

TEST(Ate, RigidlyMovedCopyHasZeroError) {
  const Trajectory gt = spiral(60);
  Trajectory est = gt;
  const Pose A = someRigidMotion();
  for (StampedPose& p : est) {
    p.T_world_cam = A * p.T_world_cam;
    p.timestamp += 0.004;  // a different clock phase, well inside 0.02 s
  }
  const AteResult r = computeAte(est, gt);
  EXPECT_EQ(r.pairs, 60);
  EXPECT_NEAR(r.rmse_m, 0.0, 1e-9);
  EXPECT_NEAR(r.max_m, 0.0, 1e-9);
  // The recovered alignment is A^-1.
  EXPECT_LT((r.T_gt_est.matrix() - A.inverse().matrix()).norm(), 1e-9);
}

TEST(Ate, KnownNoiseGivesItsAnalyticRmse) {
  // Each ground-truth position appears twice; the estimate puts +n_k on one copy and -n_k on the
  // other, then moves everything by A. The noise then has zero mean and no correlation with the
  // positions, so the best alignment is exactly A^-1 and the residuals are exactly |n_k|:
  // half are 1 cm, half 2 cm -> RMSE = sqrt((1 + 4) / 2) cm, mean 1.5 cm, max 2 cm.
  const Trajectory path = spiral(40);
  Trajectory gt, est;
  const Pose A = someRigidMotion();
  for (size_t k = 0; k < path.size(); ++k) {
    const double len = k % 2 ? 0.02 : 0.01;
    const Eigen::Vector3d n = len * Eigen::Vector3d(std::cos(1.3 * k), std::sin(1.3 * k), 0.5).normalized();
    for (int s = 0; s < 2; ++s) {
      StampedPose g = path[k];
      g.timestamp = 100.0 + 0.1 * double(2 * k + s);
      gt.push_back(g);
      StampedPose e = g;
      e.T_world_cam.translation() += (s ? -1.0 : 1.0) * n;
      e.T_world_cam = A * e.T_world_cam;
      est.push_back(e);
    }
  }
  const AteResult r = computeAte(est, gt);
  EXPECT_EQ(r.pairs, 80);
  EXPECT_NEAR(r.rmse_m, std::sqrt((0.01 * 0.01 + 0.02 * 0.02) / 2), 1e-9);
  EXPECT_NEAR(r.mean_m, 0.015, 1e-9);
  EXPECT_NEAR(r.median_m, 0.015, 1e-9);  // 40 of each: numpy's median averages 1 and 2 cm
  EXPECT_NEAR(r.max_m, 0.02, 1e-9);
  EXPECT_NEAR(r.min_m, 0.01, 1e-9);
}

TEST(Ate, UnmatchedTimestampsAreLeftOutAndTooFewPairsIsAnError) {
  const Trajectory gt = spiral(10);
  Trajectory est = gt;
  est[3].timestamp += 0.025;  // beyond 0.02 s of its own and every other ground-truth pose
  EXPECT_EQ(computeAte(est, gt).pairs, 9);
  const Trajectory two(gt.begin(), gt.begin() + 2);
  EXPECT_THROW(computeAte(two, gt), Error);
  Trajectory shifted = gt;
  for (StampedPose& p : shifted) p.timestamp += 50.0;
  EXPECT_THROW(computeAte(shifted, gt), Error);
}

TEST(Rpe, ConstantExtraYawAndStepGiveKnownErrors) {
  // Ground truth steps 10 cm along x per frame. The estimate steps 10 cm along its own x and
  // turns 2 deg about z per frame. Per pair E = D_est D_gt^-1 = [Rz(2 deg), t - Rz t]:
  // rotation 2 deg, translation |t - Rz t| = 2 * 0.1 * sin(1 deg).
  const Eigen::Vector3d step(0.1, 0, 0);
  const double yaw = 2.0 * kPi / 180.0;
  Trajectory gt, est;
  Pose g = Pose::Identity(), e = someRigidMotion();  // the estimate's world frame differs
  for (int i = 0; i < 30; ++i) {
    gt.push_back({10.0 + 0.05 * i, g});
    est.push_back({10.0 + 0.05 * i + 0.003, e});
    g = g * Eigen::Translation3d(step);
    e = e * Eigen::Translation3d(step) * Eigen::AngleAxisd(yaw, Eigen::Vector3d::UnitZ());
  }
  const RpeResult r = computeRpe(est, gt, 1);
  EXPECT_EQ(r.pairs, 29);
  EXPECT_NEAR(r.rot_rmse_deg, 2.0, 1e-7);
  EXPECT_NEAR(r.trans_rmse_m, 2 * 0.1 * std::sin(yaw / 2), 1e-9);
  EXPECT_NEAR(r.trans_max_m, r.trans_rmse_m, 1e-12);

  // delta = 3: D_est = 3 steps with 3 turns; error rotation 6 deg, and the translation part
  // is sum_k Rz(k*yaw) t - 3t for k = 0..2... computed here from the definition.
  const RpeResult r3 = computeRpe(est, gt, 3);
  EXPECT_EQ(r3.pairs, 27);
  EXPECT_NEAR(r3.rot_rmse_deg, 6.0, 1e-7);
  Pose d_est = Pose::Identity();
  for (int k = 0; k < 3; ++k) d_est = d_est * Eigen::Translation3d(step) * Eigen::AngleAxisd(yaw, Eigen::Vector3d::UnitZ());
  const Pose err = d_est * Pose(Eigen::Translation3d(3 * step)).inverse();
  EXPECT_NEAR(r3.trans_rmse_m, err.translation().norm(), 1e-9);
  EXPECT_GT(r3.trans_rmse_m, 0.01);
}

TEST(Rpe, GroundTruthAgainstItselfIsZeroAndBadDeltaThrows) {
  VF_REQUIRE_DATA(path, "tum_fr1_xyz_head100/groundtruth.txt");
  const Trajectory gt = readTumTrajectory(path);
  const RpeResult r = computeRpe(gt, gt, 1);
  EXPECT_EQ(r.pairs, int(gt.size()) - 1);
  EXPECT_NEAR(r.trans_rmse_m, 0.0, 1e-12);
  EXPECT_NEAR(r.rot_rmse_deg, 0.0, 1e-5);  // acos near 1 loses precision: ~1e-6 deg
  const AteResult a = computeAte(gt, gt);
  EXPECT_EQ(a.pairs, int(gt.size()));
  EXPECT_NEAR(a.rmse_m, 0.0, 1e-9);
  EXPECT_THROW(computeRpe(gt, gt, 0), Error);
}

TEST(TrajectoryLookup, NearestPoseWithinTolerance) {
  const Trajectory t = spiral(5);  // 100.00, 100.03, ...
  const auto p = poseNearTimestamp(t, 100.034);
  ASSERT_TRUE(p.has_value());
  EXPECT_NEAR(p->translation().x(), t[1].T_world_cam.translation().x(), 1e-15);
  EXPECT_FALSE(poseNearTimestamp(t, 100.5).has_value());
}

// TUM's associate.py as written: every pair within the tolerance, sorted by (difference, a, b),
// taken greedily. The reference the n log n association must agree with, pair for pair.
std::vector<std::pair<int, int>> associateLikeTheScript(const std::vector<double>& a, const std::vector<double>& b,
                                                        double max_difference_s, double offset_s) {
  std::vector<std::tuple<double, int, int>> candidates;
  for (int i = 0; i < int(a.size()); ++i)
    for (int j = 0; j < int(b.size()); ++j) {
      const double diff = std::abs(a[size_t(i)] - (b[size_t(j)] + offset_s));
      if (diff < max_difference_s) candidates.emplace_back(diff, i, j);
    }
  std::sort(candidates.begin(), candidates.end());
  std::vector<char> a_used(a.size()), b_used(b.size());
  std::vector<std::pair<int, int>> matches;
  for (const auto& [diff, i, j] : candidates)
    if (!a_used[size_t(i)] && !b_used[size_t(j)]) a_used[size_t(i)] = b_used[size_t(j)] = 1, matches.emplace_back(i, j);
  std::sort(matches.begin(), matches.end());
  return matches;
}

TEST(Associate, SameMatchesAsTumsScriptWithTiesAndOffsets) {
  std::mt19937 rng(35);
  // Timestamps on a coarse grid so that equal values and equal differences are common.
  for (int trial = 0; trial < 20000; ++trial) {
    const int levels = 1 + int(rng() % 10);
    const double step = trial % 2 ? 0.01 : 0.003;
    std::vector<double> a(rng() % 12), b(rng() % 12);
    for (double& t : a) t = 50.0 + double(rng() % unsigned(levels)) * step;
    for (double& t : b) t = 50.0 + double(rng() % unsigned(levels)) * step;
    const double max_difference = trial % 3 ? 0.02 : double(rng() % 5) * 0.005;
    const double offset = trial % 4 ? 0.0 : 0.003;
    ASSERT_EQ(associateTimestamps(a, b, max_difference, offset), associateLikeTheScript(a, b, max_difference, offset))
        << "trial " << trial;
  }
  std::uniform_real_distribution<double> u(0, 2);
  for (int trial = 0; trial < 200; ++trial) {
    std::vector<double> a(300), b(250);
    for (double& t : a) t = u(rng);
    for (double& t : b) t = u(rng);
    ASSERT_EQ(associateTimestamps(a, b), associateLikeTheScript(a, b, kTumMaxTimeDifference_s, 0)) << trial;
  }
}

// Issue 35: 8,000 poses 1 us apart took 1 GB (every pair within 0.02 s was listed), 20,000 more
// than 6 GB. In a child under an address-space limit of 256 MiB more than it has mapped, the
// 20,000 must associate (old code: std::bad_alloc, status 3).
TEST(Associate, DenseTimestampsNeedMemoryLinearInTheirCount) {
  std::vector<double> a(20000), b(20000);
  for (size_t i = 0; i < a.size(); ++i) a[i] = 1000.0 + 1e-6 * double(i), b[i] = a[i] + 0.4e-6;
  const pid_t pid = fork();
  ASSERT_GE(pid, 0);
  if (pid == 0) {
    unsigned long long pages = 0;
    std::FILE* statm = std::fopen("/proc/self/statm", "r");
    if (!statm || std::fscanf(statm, "%llu", &pages) != 1) _exit(4);
    std::fclose(statm);
    const rlim_t limit = rlim_t(pages) * rlim_t(sysconf(_SC_PAGESIZE)) + (rlim_t(256) << 20);
    const rlimit as{limit, limit};
    if (setrlimit(RLIMIT_AS, &as) != 0) _exit(5);
    try {
      const auto matches = associateTimestamps(a, b);
      // Each a[i] is nearest to b[i] (0.4 us; the next is 0.6 us away).
      for (size_t i = 0; i < matches.size(); ++i)
        if (matches[i] != std::pair<int, int>(int(i), int(i))) _exit(2);
      _exit(matches.size() == a.size() ? 0 : 1);
    } catch (const std::bad_alloc&) {
      _exit(3);
    }
  }
  int status = 0;
  ASSERT_EQ(waitpid(pid, &status, 0), pid);
  ASSERT_TRUE(WIFEXITED(status)) << "the child died of signal " << WTERMSIG(status);
  EXPECT_EQ(WEXITSTATUS(status), 0) << "1: not every pose matched, 2: wrong pairs, 3: out of memory";
}

TEST(Ate, AbsurdPositionsAreRefusedNotPrintedAsInfinity) {
  Trajectory gt = spiral(10), est = gt;
  est[4].T_world_cam.translation() = Eigen::Vector3d(1e300, 0, 0);
  const std::string message = test::errorOf([&] { requirePlausiblePositions(est, "est.txt"); });
  EXPECT_NE(message.find("est.txt: pose 5 (t = 100.120000) is at (1e+300, 0, 0) m"), std::string::npos) << message;
  EXPECT_EQ(test::errorOf([&] { requirePlausiblePositions(gt, "gt.txt"); }), "(no error)");
  // Past the check (the library called directly), the statistics overflow: an error, not inf.
  EXPECT_NE(test::errorOf([&] { computeAte(est, gt); }).find("the ATE is not finite"), std::string::npos);
  EXPECT_NE(test::errorOf([&] { computeRpe(est, gt); }).find("the RPE is not finite"), std::string::npos);
}

}  // namespace
}  // namespace vf
