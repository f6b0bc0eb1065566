#pragma once
// A keyframe's surface, small enough to keep for every keyframe of a long run: its depth on a
// grid about 160 points wide (a quarter of a VGA frame), as camera-frame points and normals. Two
// keyframes' clouds are aligned by point-to-plane ICP with projective association (as tracking,
// Newcombe et al. 2011, but frame to frame and on the host): the check and the measurement of a
// loop closure, and of the odometry between consecutive keyframes.
#include <optional>
#include <vector>

#include "core/frame.h"
#include "core/intrinsics.h"
#include "core/pose.h"

namespace vf::slam {

struct KeyframeCloud {
  Intrinsics camera;              // of the grid
  std::vector<Vec3f> points;      // camera frame; z = 0 where there is none
  std::vector<Vec3f> normals;     // unit, towards the camera; zero where there is none
  bool empty() const { return points.empty(); }
};

// Every `step`-th pixel's depth (the median of the valid ones in its block) within the range.
// step 0: the grid about kKeyframeCloudWidth points wide, whatever the camera's resolution.
KeyframeCloud makeKeyframeCloud(const DepthImage& depth, const Intrinsics& camera, float min_depth_m,
                                float max_depth_m, int step = 0);
// A quarter of a VGA frame. The grid's spacing is what its normals and the alignment's tests see:
// at a quarter of a 320x240 frame (80x60) every normal of a corridor's walls seen at a grazing
// angle straddled a depth step, and none of the ring corridor's 342 candidate loops aligned.
constexpr int kKeyframeCloudWidth = 160;

struct CloudAlignment {
  Pose T_target_source = Pose::Identity();
  float overlap = 0;        // share of the source's points with a partner in the target
  float rmse_m = 0;         // point-to-plane, over the partners
  int partners = 0;
  // The Gauss-Newton information of the camera-frame increment (omega, v) of the source, from the
  // partners' rows, in 1/m^2 of point-to-plane residual (for a pose graph edge).
  Eigen::Matrix<double, 6, 6> information = Eigen::Matrix<double, 6, 6>::Zero();
  // The weakest translation direction's share of the partners' constraint on translation (the
  // smallest eigenvalue of the information's translation block over its trace): 1/3 when the
  // surfaces face every way, near 0 when they leave a direction free (one wall, a corridor seen
  // along its length).
  double weakestTranslationShare() const;
};

// Point-to-plane ICP of source onto target from `initial`, with partners within max_distance_m
// and normals within 30 degrees; nullopt when too few partners remain.
std::optional<CloudAlignment> alignClouds(const KeyframeCloud& source, const KeyframeCloud& target,
                                          const Pose& initial, float max_distance_m = 0.05f, int iterations = 15);

}  // namespace vf::slam
