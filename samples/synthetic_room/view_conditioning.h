#pragma once
// How well one view pins the camera down for point-to-plane ICP: the eigenvalues of the 6x6
// normal matrix sum J J^T, J = (l x n, n), over the view's points (lever arms l about their
// centroid, in units of their RMS spread, so rotations and translations weigh alike) and the
// true normals n. A view of one plane leaves three eigenvalues at 0 (two translations along
// it, the rotation about its normal); a corridor with nothing on its walls leaves one (along
// the corridor).
#include <Eigen/Core>

#include "core/intrinsics.h"
#include "core/pose.h"
#include "room_geometry.h"
#include "room_render.h"

namespace vf::synth {

// Ascending eigenvalues over the largest (the last is 1); all 0 when fewer than 6 pixels have
// depth in [min_depth_m, max_depth_m].
Eigen::Matrix<double, 6, 1> icpConditioning(const Room& room, const CleanView& view, const Intrinsics& k,
                                            const Pose& T_world_cam, float min_depth_m = 0.4f, float max_depth_m = 4.f);

// How many of the six directions are weaker than `ratio` times the strongest.
int weakDirections(const Eigen::Matrix<double, 6, 1>& conditioning, double ratio = 1e-3);

}  // namespace vf::synth
