#pragma once
// Keyframe poses made consistent with every relative measurement between them: odometry edges
// between consecutive keyframes (what tracking measured) and loop edges (a place seen again),
// each with an information matrix, optimised by Ceres (Levenberg-Marquardt, sparse Cholesky).
// Loop edges go through a robust (Cauchy) loss, and a loop that still disagrees with the rest
// after the optimisation is switched off and the graph solved again without it, so that one wrong
// loop cannot bend the map (as Open3D's line process prunes its edges).
#include <vector>

#include "core/pose.h"

namespace vf::slam {

struct PoseGraphEdge {
  int from = 0, to = 0;                 // node indices
  Pose T_from_to = Pose::Identity();    // measured: the pose of `to` in the frame of `from`
  // Of the right increment (omega, v) of T_from_to, in 1/rad^2 and 1/m^2.
  Eigen::Matrix<double, 6, 6> information = Eigen::Matrix<double, 6, 6>::Identity();
  bool loop = false;
};

struct PoseGraphResult {
  std::vector<Pose> poses;
  std::vector<bool> loop_kept;          // per edge: false for a loop edge switched off
  int rounds = 0;                       // optimisations run (one more per round of switching off)
};

struct PoseGraphParams {
  double loop_loss_scale = 3.0;         // Cauchy scale, in standard deviations of the edge
  double max_loop_chi = 5.0;            // a loop still this many deviations off after solving is switched off
  int max_rounds = 5;
  void validate() const;
};

// Node 0 stays fixed (the world is its frame). Throws vf::Error for an edge naming a missing node.
PoseGraphResult optimisePoseGraph(const std::vector<Pose>& initial, const std::vector<PoseGraphEdge>& edges,
                                  const PoseGraphParams& params = {});

// The whitened size of an edge's disagreement with the poses: sqrt(e^T I e).
double edgeChi(const PoseGraphEdge& edge, const std::vector<Pose>& poses);

}  // namespace vf::slam
