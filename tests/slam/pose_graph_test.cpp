// The pose graph (slam/pose_graph.h) on a walk round a square whose odometry drifts: one right
// loop pulls the end back onto the start, and a wrong loop is switched off instead of bending
// the map.
#include <gtest/gtest.h>

#include <cmath>

#include "slam/pose_graph.h"
#include "square_walk.h"

namespace vf::slam {
namespace {

using test::poseAt;
using test::squareWalk;

Eigen::Matrix<double, 6, 6> information(double sigma_m, double sigma_deg) {
  Eigen::Matrix<double, 6, 6> info = Eigen::Matrix<double, 6, 6>::Zero();
  const double r = sigma_deg * M_PI / 180.0;
  info.diagonal() << 1 / (r * r), 1 / (r * r), 1 / (r * r), 1 / (sigma_m * sigma_m), 1 / (sigma_m * sigma_m),
      1 / (sigma_m * sigma_m);
  return info;
}

struct Graph {
  std::vector<Pose> truth, odometry;
  std::vector<PoseGraphEdge> edges;
};

// Odometry edges that each turn 0.5 degree too far: the end lands about a metre from the start.
Graph driftingSquare() {
  Graph g;
  g.truth = squareWalk();
  const Pose bias = poseAt(0, 0, 0.5);
  g.odometry.push_back(g.truth[0]);
  for (size_t i = 0; i + 1 < g.truth.size(); ++i) {
    PoseGraphEdge e;
    e.from = int(i);
    e.to = int(i + 1);
    e.T_from_to = (g.truth[i].inverse() * g.truth[i + 1]) * bias;
    e.information = information(0.01, 0.5);
    g.edges.push_back(e);
    g.odometry.push_back(g.odometry.back() * e.T_from_to);
  }
  return g;
}

PoseGraphEdge loop(const Graph& g, int from, int to, const Pose& error = Pose::Identity()) {
  PoseGraphEdge e;
  e.from = from;
  e.to = to;
  e.T_from_to = g.truth[size_t(from)].inverse() * g.truth[size_t(to)] * error;
  e.information = information(0.02, 1.0);
  e.loop = true;
  return e;
}

TEST(PoseGraph, ALoopPullsADriftingWalkBackOntoItsStart) {
  Graph g = driftingSquare();
  const double drift = test::worstOffsetM(g.odometry, g.truth);
  ASSERT_GT(drift, 0.5);
  g.edges.push_back(loop(g, 0, 39));
  const PoseGraphResult r = optimisePoseGraph(g.odometry, g.edges);
  EXPECT_TRUE(r.loop_kept.back());
  // The gap at the end closes; what stays is the bend that a turn biased the same way at every
  // step leaves along the way (one loop cannot tell where on the walk the turning was wrong).
  EXPECT_LT((r.poses.back().translation() - g.truth.back().translation()).norm(), 0.05 * drift);
  EXPECT_LT(test::worstOffsetM(r.poses, g.truth), 0.15 * drift) << "odometry was " << drift << " m off";
  EXPECT_TRUE(r.poses[0].isApprox(g.odometry[0])) << "node 0 is the world's frame and stays";
}

TEST(PoseGraph, AWrongLoopIsSwitchedOffAndDoesNotBendTheMap) {
  Graph g = driftingSquare();
  g.edges.push_back(loop(g, 0, 39));
  g.edges.push_back(loop(g, 1, 38));
  // Two places that look alike: node 20 (the far corner) claimed to be beside node 5, 2 m off.
  g.edges.push_back(loop(g, 5, 20, poseAt(1.5, 1.2, 40)));
  const PoseGraphResult r = optimisePoseGraph(g.odometry, g.edges);
  ASSERT_EQ(r.loop_kept.size(), g.edges.size());
  EXPECT_FALSE(r.loop_kept.back()) << "the wrong loop was kept";
  EXPECT_TRUE(r.loop_kept[g.edges.size() - 2]);
  EXPECT_TRUE(r.loop_kept[g.edges.size() - 3]);
  EXPECT_LT(test::worstOffsetM(r.poses, g.truth), 0.1);
}

TEST(PoseGraph, WithoutLoopsTheOdometryStands) {
  const Graph g = driftingSquare();
  const PoseGraphResult r = optimisePoseGraph(g.odometry, g.edges);
  EXPECT_LT(test::worstOffsetM(r.poses, g.odometry), 1e-6);
}

}  // namespace
}  // namespace vf::slam
