#include "view_conditioning.h"

#include <Eigen/Eigenvalues>

#include <vector>

namespace vf::synth {

Eigen::Matrix<double, 6, 1> icpConditioning(const Room& room, const CleanView& view, const Intrinsics& k, const Pose& T,
                                            float min_depth_m, float max_depth_m) {
  std::vector<Eigen::Vector3d> points, normals;
  for (int y = 0; y < k.height; ++y)
    for (int x = 0; x < k.width; ++x) {
      const float z = view.depth(x, y);
      if (z < min_depth_m || z > max_depth_m) continue;
      const Eigen::Vector3d p = T * Eigen::Vector3d((x - k.cx) / k.fx * z, (y - k.cy) / k.fy * z, z);
      const int prim = view.primitive[size_t(y) * size_t(k.width) + size_t(x)];
      points.push_back(p);
      normals.push_back(surfaceNormal(room.primitives[size_t(prim)], p.cast<float>()).cast<double>());
    }
  if (points.size() < 6) return Eigen::Matrix<double, 6, 1>::Zero();
  Eigen::Vector3d centroid = Eigen::Vector3d::Zero();
  for (const auto& p : points) centroid += p;
  centroid /= double(points.size());
  double spread = 0;
  for (const auto& p : points) spread += (p - centroid).squaredNorm();
  spread = std::sqrt(spread / double(points.size()));
  Eigen::Matrix<double, 6, 6> H = Eigen::Matrix<double, 6, 6>::Zero();
  for (size_t i = 0; i < points.size(); ++i) {
    const Eigen::Vector3d l = (points[i] - centroid) / spread, &n = normals[i];
    Eigen::Matrix<double, 6, 1> J;  // (l x n, n), the cross product spelled out: GCC 12 warns on Eigen's AVX one
    J << l.y() * n.z() - l.z() * n.y(), l.z() * n.x() - l.x() * n.z(), l.x() * n.y() - l.y() * n.x(), n;
    H += J * J.transpose();
  }
  const Eigen::SelfAdjointEigenSolver<Eigen::Matrix<double, 6, 6>> eig(H);
  return eig.eigenvalues() / eig.eigenvalues()(5);
}

int weakDirections(const Eigen::Matrix<double, 6, 1>& conditioning, double ratio) {
  int weak = 0;
  for (int i = 0; i < 6; ++i) weak += conditioning(i) < ratio;
  return weak;
}

}  // namespace vf::synth
