#pragma once
// Which voxel lies on the surface, and where on it: the rule shared by the point cloud of a
// scene's grids (scenePointCloud) and of the fused bricks (brickSurfaceSamples), so that both
// give the same points.
#include <array>
#include <cmath>

namespace vf {

// A voxel with signed distance v (metres) is a surface sample when an observed 6-neighbour has
// the opposite sign and v is the nearer of the two to zero. Its normal is the central-difference
// gradient (one-sided where a neighbour is unobserved), and its point the voxel centre moved by
// -v along the normal (the caller adds it, in double). `neighbour(axis, side, value)` (side -1
// or +1) returns whether that neighbour is observed and, if so, its distance. Returns false for
// no sample.
template <class Neighbour>
bool surfaceSample(float v, double voxel_m, const Neighbour& neighbour, std::array<double, 3>& normal) {
  bool crossing = false;
  double grad[3];
  for (int a = 0; a < 3; ++a) {
    float vl = 0, vh = 0;
    const bool ol = neighbour(a, -1, vl), oh = neighbour(a, +1, vh);
    if (ol && (vl < 0) != (v < 0) && std::fabs(v) <= std::fabs(vl)) crossing = true;
    if (oh && (vh < 0) != (v < 0) && std::fabs(v) <= std::fabs(vh)) crossing = true;
    grad[a] = ol && oh ? (vh - vl) / (2 * voxel_m) : oh ? (vh - v) / voxel_m : ol ? (v - vl) / voxel_m : 0.0;
  }
  if (!crossing) return false;
  const double len = std::sqrt(grad[0] * grad[0] + grad[1] * grad[1] + grad[2] * grad[2]);
  normal = len > 0 ? std::array<double, 3>{grad[0] / len, grad[1] / len, grad[2] / len} : std::array<double, 3>{0, 0, 1};
  return true;
}

}  // namespace vf
