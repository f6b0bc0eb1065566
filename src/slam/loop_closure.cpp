#include "slam/loop_closure.h"

#include <algorithm>
#include <Eigen/Eigenvalues>
#include <cmath>
#include <functional>
#include <set>

#include "core/error.h"

namespace vf::slam {
namespace {

// The alignment's information has the right shape (a corridor constrains little along itself,
// a view of one wall nothing along it) but not the right size: it treats thousands of point
// residuals as independent, and claims a hundredth of a millimetre. Scaled so that the mean
// translation axis has a standard deviation of sigma_m, the size of the errors edges really have
// (the tracker's drift between keyframes, a loop's misalignment).
Eigen::Matrix<double, 6, 6> edgeInformation(const CloudAlignment& a, double sigma_m) {
  const double translation_trace = a.information.bottomRightCorner<3, 3>().trace();
  if (!(translation_trace > 0)) return Eigen::Matrix<double, 6, 6>::Identity() / (sigma_m * sigma_m);
  return a.information * (3.0 / translation_trace) / (sigma_m * sigma_m);
}

// Of (omega, v): the same information in each rotation axis (1/rad^2) and each translation axis (1/m^2).
Eigen::Matrix<double, 6, 6> isotropicInformation(double per_rotation_axis, double per_translation_axis) {
  Eigen::Matrix<double, 6, 6> information = Eigen::Matrix<double, 6, 6>::Zero();
  information.diagonal() << Eigen::Vector3d::Constant(per_rotation_axis), Eigen::Vector3d::Constant(per_translation_axis);
  return information;
}

// The information with the variance of the translation along each of its directions grown by
// (sigma_m * min(1, free_share / share))^2, share being the direction's share of the translation
// block's trace: a direction constrained that little or less is free, and the error along a
// direction constrained more falls as its constraint grows (a bias in the residuals moves a
// least-squares solution by the bias over the curvature).
Eigen::Matrix<double, 6, 6> weakenFreeTranslation(const Eigen::Matrix<double, 6, 6>& information, double sigma_m,
                                                  double free_share) {
  const Eigen::Matrix<double, 6, 6> symmetric = 0.5 * (information + information.transpose());
  const Eigen::SelfAdjointEigenSolver<Eigen::Matrix3d> translation(symmetric.bottomRightCorner<3, 3>());
  const double trace = translation.eigenvalues().sum();
  if (!(trace > 0)) return information;
  Eigen::Matrix<double, 6, 6> added = Eigen::Matrix<double, 6, 6>::Zero();
  for (int k = 0; k < 3; ++k) {
    const double share = std::max(0.0, translation.eigenvalues()(k)) / trace;
    const double sigma = sigma_m * std::min(1.0, free_share / std::max(share, 1e-12));
    const Eigen::Vector3d v = translation.eigenvectors().col(k);
    added.bottomRightCorner<3, 3>() += sigma * sigma * v * v.transpose();
  }
  // Covariance = information^-1, on a floor of 1e-9 of the strongest eigenvalue (as the pose
  // graph's square root does).
  const Eigen::SelfAdjointEigenSolver<Eigen::Matrix<double, 6, 6>> eigen(symmetric);
  const double floor = std::max(1e-12, 1e-9 * eigen.eigenvalues().maxCoeff());
  const Eigen::Matrix<double, 6, 6> covariance = eigen.eigenvectors() *
                                                 eigen.eigenvalues().cwiseMax(floor).cwiseInverse().asDiagonal() *
                                                 eigen.eigenvectors().transpose();
  const Eigen::Matrix<double, 6, 6> weakened = (covariance + added).inverse();
  return 0.5 * (weakened + weakened.transpose());
}

// The two views aligned from `start` with partners up to 30 cm apart, then 10, then 5 cm (the
// last stage's statistics are those judged). From 5 cm alone, a start as far off as the ring
// corridor's odometry at its return (35 cm) finds too few partners: 315 of its 365 candidate
// pairs aligned to nothing, 2 loops were found; coarse to fine, 19.
std::optional<CloudAlignment> alignCoarseToFine(const KeyframeCloud& source, const KeyframeCloud& target,
                                                const Pose& start) {
  std::optional<CloudAlignment> a = alignClouds(source, target, start, 0.3f, 10);
  if (a) a = alignClouds(source, target, a->T_target_source, 0.1f, 10);
  if (a) a = alignClouds(source, target, a->T_target_source, 0.05f, 20);
  return a;
}

// A return the odometry puts far off along a direction the tracker could not see is beyond the
// coarse stage's 30 cm: the candidate is aligned again from starts slid along the newer camera's
// viewing and sideways axes (LoopParams::max_slide_m). Kept only when every slid start that
// aligns agrees on one place within `agree_m`: a corridor whose doors repeat offers several.
std::optional<CloudAlignment> alignFromSlidStarts(const KeyframeCloud& source, const KeyframeCloud& target,
                                                  const Pose& start, const LoopParams& params,
                                                  const std::function<bool(const std::optional<CloudAlignment>&)>& accepted) {
  constexpr double agree_m = 0.1;
  std::optional<CloudAlignment> best;
  for (const int axis : {2, 0}) {  // viewing, then sideways
    for (double slide = params.slide_step_m; slide <= params.max_slide_m + 1e-9; slide += params.slide_step_m) {
      for (const double sign : {-1.0, 1.0}) {
        Pose slid = start;
        slid.translation() += start.linear().col(axis) * (sign * slide);
        const std::optional<CloudAlignment> a = alignCoarseToFine(source, target, slid);
        if (!accepted(a)) continue;
        if (best && (best->T_target_source.translation() - a->T_target_source.translation()).norm() > agree_m)
          return std::nullopt;  // two places
        if (!best || a->overlap > best->overlap) best = a;
      }
    }
  }
  return best;
}

// The walk's usual pace, metres a frame: the median over consecutive keyframes of one map.
double medianPace(const KeyframeStore& keyframes) {
  std::vector<double> pace;
  for (int i = 0; i + 1 < keyframes.size(); ++i) {
    const Keyframe& a = keyframes[i];
    const Keyframe& b = keyframes[i + 1];
    const int frames = b.frame_index - a.frame_index;
    if (a.map != b.map || frames <= 0) continue;
    pace.push_back((b.T_world_cam.translation() - a.T_world_cam.translation()).norm() / frames);
  }
  if (pace.empty()) return 0.0;
  std::nth_element(pace.begin(), pace.begin() + std::ptrdiff_t(pace.size() / 2), pace.end());
  return pace[pace.size() / 2];
}

}  // namespace

void LoopParams::validate() const {
  if (min_separation_frames < 1 || candidates_by_code < 0 || candidates_by_place < 0 || !(min_overlap > 0) ||
      !(max_slide_m >= 0) || !(slide_step_m > 0) || min_held_frames_to_slide < 0 ||
      !(max_rmse_m > 0) || !(loop_sigma_m > 0) || !(odometry_sigma_m > 0) || !(odometry_drift >= 0) ||
      !(prior_held_drift >= 0) || !(free_translation_share >= 0 && free_translation_share <= 1.0 / 3.0) ||
      !(max_candidate_distance_m > 0) || !(min_translation_share >= 0 && min_translation_share <= 1.0 / 3.0) ||
      !(new_map_sigma_m > 0) || !(new_map_sigma_deg > 0))
    throw Error("LoopParams: separations, counts and limits must be positive, min_translation_share in [0, 1/3]");
}

std::vector<PoseGraphEdge> odometryEdges(const KeyframeStore& keyframes, const LoopParams& params,
                                         const std::vector<PriorHeldStretch>& prior_held) {
  std::vector<PoseGraphEdge> edges;
  const double pace_m = medianPace(keyframes);
  for (int i = 0; i + 1 < keyframes.size(); ++i) {
    const Keyframe& a = keyframes[i];
    const Keyframe& b = keyframes[i + 1];
    PoseGraphEdge e;
    e.from = i;
    e.to = i + 1;
    e.T_from_to = a.T_world_cam.inverse() * b.T_world_cam;
    // Into a new map: only the guess of where the camera's recent pace led (new_map_sigma_*).
    if (a.map != b.map) {
      const double sigma_rad = params.new_map_sigma_deg * M_PI / 180.0;
      e.information = isotropicInformation(1.0 / (sigma_rad * sigma_rad), 1.0 / (params.new_map_sigma_m * params.new_map_sigma_m));
      edges.push_back(e);
      continue;
    }
    // The information of the two views' depth at the tracked relative pose (no refinement: the
    // measurement stays the tracker's, which saw every frame in between). Where the views share
    // too little (a relocalisation across a gap), a weak isotropic information of 1 cm / 1 degree.
    const auto aligned = alignClouds(b.cloud, a.cloud, e.T_from_to, 0.1f, 0);
    if (aligned && aligned->overlap >= params.min_overlap) {
      // Tracking drifts by about a percent of the distance travelled, and a few millimetres anyway.
      const double sigma = params.odometry_sigma_m + params.odometry_drift * e.T_from_to.translation().norm();
      e.information = edgeInformation(*aligned, sigma);
      const int frames = b.frame_index - a.frame_index;
      const int held = priorHeldFramesBetween(prior_held, a.frame_index, b.frame_index);
      if (held > 0 && frames > 0 && params.prior_held_drift > 0) {
        // What the held frames travelled, at least at the walk's pace: a slide that turned back
        // shrinks the tracked distance, not the doubt.
        const double held_distance = std::max(e.T_from_to.translation().norm() * held / frames, pace_m * held);
        e.information = weakenFreeTranslation(e.information, params.prior_held_drift * held_distance,
                                              params.free_translation_share);
      }
    } else {
      e.information = isotropicInformation(1.0 / 3e-4, 1e4);
    }
    edges.push_back(e);
  }
  return edges;
}

std::vector<PoseGraphEdge> detectLoops(const KeyframeStore& keyframes, const LoopParams& params, LoopStats* stats,
                                       const std::vector<PriorHeldStretch>& prior_held,
                                       const std::vector<Pose>& search_poses) {
  params.validate();
  if (!search_poses.empty() && int(search_poses.size()) != keyframes.size())
    throw Error("detectLoops: one search pose per keyframe");
  // Where to look from: the keyframes' own poses, and the other placement where given (each finds
  // its own candidates by place and its own odometry's guess).
  std::vector<Pose> own(size_t(keyframes.size()));
  for (int i = 0; i < keyframes.size(); ++i) own[size_t(i)] = keyframes[i].T_world_cam;
  std::vector<const std::vector<Pose>*> placements{&own};
  if (!search_poses.empty()) placements.push_back(&search_poses);
  std::vector<PoseGraphEdge> loops;
  LoopStats local;
  for (int j = 0; j < keyframes.size(); ++j) {
    const Keyframe& newer = keyframes[j];
    std::vector<std::pair<float, int>> by_code;
    std::vector<std::vector<std::pair<float, int>>> by_place(placements.size());
    for (int i = 0; i < j; ++i) {
      const Keyframe& older = keyframes[i];
      if (newer.frame_index - older.frame_index < params.min_separation_frames) continue;
      const float d = FernEncoder::dissimilarity(newer.code, older.code);
      if (d <= params.max_code_dissimilarity) by_code.push_back({d, i});
      for (size_t p = 0; p < placements.size(); ++p) {
        const Pose& Tj = (*placements[p])[size_t(j)];
        const Pose& Ti = (*placements[p])[size_t(i)];
        const double distance = (Tj.translation() - Ti.translation()).norm();
        if (distance <= params.max_candidate_distance_m && rotationDeg(Tj.inverse() * Ti) <= params.max_candidate_angle_deg)
          by_place[p].push_back({float(distance), i});
      }
    }
    std::sort(by_code.begin(), by_code.end());
    std::set<int> candidates;
    for (size_t k = 0; k < by_code.size() && int(k) < params.candidates_by_code; ++k) candidates.insert(by_code[k].second);
    for (std::vector<std::pair<float, int>>& nearest : by_place) {
      std::sort(nearest.begin(), nearest.end());
      for (size_t k = 0; k < nearest.size() && int(k) < params.candidates_by_place; ++k) candidates.insert(nearest[k].second);
    }
    for (int i : candidates) {
      const Keyframe& older = keyframes[i];
      ++local.candidates;
      // The odometry's guess, and the other placement's where it differs (a later map turned);
      // the point features' start before them.
      std::vector<Pose> guesses{own[size_t(i)].inverse() * own[size_t(j)]};
      for (size_t p = 1; p < placements.size(); ++p) {
        const Pose other = (*placements[p])[size_t(i)].inverse() * (*placements[p])[size_t(j)];
        if (!other.isApprox(guesses[0], 1e-9)) guesses.push_back(other);
      }
      std::vector<Pose> starts = guesses;
      if (const auto features = estimateRelativePose(newer.features, older.features, 20))
        starts.insert(starts.begin(), features->T_target_source);
      std::optional<CloudAlignment> best;
      auto accepted = [&](const std::optional<CloudAlignment>& a) {
        return a && a->overlap >= params.min_overlap && a->rmse_m <= params.max_rmse_m &&
               a->weakestTranslationShare() >= params.min_translation_share;
      };
      for (const Pose& start : starts) {
        std::optional<CloudAlignment> a = alignClouds(newer.cloud, older.cloud, start, 0.05f, 20);
        if (!accepted(a)) a = alignCoarseToFine(newer.cloud, older.cloud, start);  // a start further off
        if (accepted(a) && (!best || a->overlap > best->overlap)) best = a;
      }
      // Only where tracking leaned on its motion prior between the two can it have slid that far
      // unnoticed; elsewhere a start that far off is a different place (7-Scenes kitchen, 500
      // frames: 33 more loops from slid starts, 32 of them rejected by the pose graph).
      if (!best && params.max_slide_m > 0 &&
          priorHeldFramesBetween(prior_held, older.frame_index, newer.frame_index) >= params.min_held_frames_to_slide)
        for (size_t g = 0; g < guesses.size() && !best; ++g)
          best = alignFromSlidStarts(newer.cloud, older.cloud, guesses[g], params, accepted);
      if (!best) continue;
      ++local.verified;
      PoseGraphEdge e;
      e.from = i;
      e.to = j;
      e.T_from_to = best->T_target_source;
      e.information = edgeInformation(*best, std::max(double(best->rmse_m), double(params.loop_sigma_m)));
      e.loop = true;
      loops.push_back(e);
    }
  }
  if (stats) *stats = local;
  return loops;
}

}  // namespace vf::slam
