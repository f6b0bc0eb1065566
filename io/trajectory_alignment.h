#pragma once
// The rigid motion that brings an estimated trajectory (and what was fused along it) into the
// frame of its ground truth, for comparing a reconstruction with a reference mesh.
#include <string>

#include "core/pose.h"

namespace vf {

enum class AlignmentMethod {
  Auto,       // Ate, unless the positions are too close to a line to fix the rotation: First
  Ate,        // the ATE's least-squares rigid alignment of the positions (Horn / Umeyama)
  FirstPose,  // the first estimated pose onto its ground-truth pose (orientation included)
  None,       // identity
};

// Parses "auto" / "ate" / "first" / "none"; throws vf::Error otherwise.
AlignmentMethod parseAlignmentMethod(const std::string& text);

struct TrajectoryAlignment {
  Pose T_gt_est = Pose::Identity();  // ground truth ~ T_gt_est * estimate
  AlignmentMethod method = AlignmentMethod::None;
  int pairs = 0;                     // associated poses (Ate) or 1 (FirstPose)
  std::string description;           // says which alignment was applied, for the user
};

// Positions whose spread across their main direction is under this do not fix a rotation about
// it (a camera moving along a line); Auto then aligns by the first pose instead.
constexpr double kMinLateralSpread_m = 0.01;

// Throws vf::Error when the trajectories share no timestamp (within TUM's 0.02 s), or Ate has
// fewer than 3 pairs.
TrajectoryAlignment alignTrajectory(const Trajectory& estimate, const Trajectory& ground_truth,
                                    AlignmentMethod method);

}  // namespace vf
