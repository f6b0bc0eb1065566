#include "slam/keyframe_cloud.h"

#include <Eigen/Cholesky>
#include <Eigen/Eigenvalues>

#include <algorithm>
#include <array>
#include <cmath>

namespace vf::slam {

KeyframeCloud makeKeyframeCloud(const DepthImage& depth, const Intrinsics& camera, float min_depth_m,
                                float max_depth_m, int step) {
  KeyframeCloud cloud;
  if (step <= 0) step = std::max(1, int(std::lround(double(depth.width()) / kKeyframeCloudWidth)));
  const int w = depth.width() / step, h = depth.height() / step;
  if (w < 3 || h < 3) return cloud;
  cloud.camera = camera;
  cloud.camera.fx = camera.fx / float(step);
  cloud.camera.fy = camera.fy / float(step);
  cloud.camera.cx = (camera.cx + 0.5f) / float(step) - 0.5f;
  cloud.camera.cy = (camera.cy + 0.5f) / float(step) - 0.5f;
  cloud.camera.width = w;
  cloud.camera.height = h;
  cloud.points.assign(size_t(w) * h, Vec3f{0, 0, 0});
  cloud.normals.assign(size_t(w) * h, Vec3f{0, 0, 0});
  std::vector<float> block;
  for (int y = 0; y < h; ++y)
    for (int x = 0; x < w; ++x) {
      block.clear();
      for (int dy = 0; dy < step; ++dy)
        for (int dx = 0; dx < step; ++dx) {
          const float z = depth(x * step + dx, y * step + dy);
          if (z >= min_depth_m && z <= max_depth_m) block.push_back(z);
        }
      if (int(block.size()) * 2 < step * step) continue;  // mostly holes: an edge or a dropout
      std::nth_element(block.begin(), block.begin() + long(block.size() / 2), block.end());
      cloud.points[size_t(y) * w + x] = cloud.camera.backProject(float(x), float(y), block[block.size() / 2]);
    }
  for (int y = 1; y + 1 < h; ++y)
    for (int x = 1; x + 1 < w; ++x) {
      const Vec3f& l = cloud.points[size_t(y) * w + x - 1];
      const Vec3f& r = cloud.points[size_t(y) * w + x + 1];
      const Vec3f& u = cloud.points[size_t(y - 1) * w + x];
      const Vec3f& d = cloud.points[size_t(y + 1) * w + x];
      const Vec3f& c = cloud.points[size_t(y) * w + x];
      if (l.z <= 0 || r.z <= 0 || u.z <= 0 || d.z <= 0 || c.z <= 0) continue;
      // Neighbours across a depth jump belong to another surface.
      const float jump = 0.05f * c.z;
      if (std::fabs(l.z - r.z) > jump || std::fabs(u.z - d.z) > jump) continue;
      const Eigen::Vector3f a(r.x - l.x, r.y - l.y, r.z - l.z), b(d.x - u.x, d.y - u.y, d.z - u.z);
      Eigen::Vector3f n = a.cross(b);
      if (n.norm() < 1e-12f) continue;
      n.normalize();
      if (n.dot(Eigen::Vector3f(c.x, c.y, c.z)) > 0) n = -n;
      cloud.normals[size_t(y) * w + x] = Vec3f{n.x(), n.y(), n.z()};
    }
  return cloud;
}

std::optional<CloudAlignment> alignClouds(const KeyframeCloud& source, const KeyframeCloud& target,
                                          const Pose& initial, float max_distance_m, int iterations) {
  if (source.empty() || target.empty()) return std::nullopt;
  const double min_cos = std::cos(30.0 * M_PI / 180.0);
  const Intrinsics& k = target.camera;
  Pose T = initial;
  CloudAlignment result;
  int valid_source = 0;
  for (size_t i = 0; i < source.points.size(); ++i) valid_source += source.normals[i].z != 0 || source.normals[i].x != 0 ? 1 : 0;
  if (valid_source < 50) return std::nullopt;
  for (int it = 0; it <= iterations; ++it) {
    Eigen::Matrix<double, 6, 6> A = Eigen::Matrix<double, 6, 6>::Zero();
    Eigen::Matrix<double, 6, 1> g = Eigen::Matrix<double, 6, 1>::Zero();
    double squared = 0;
    int partners = 0;
    const Eigen::Matrix3d R = T.linear();
    for (size_t i = 0; i < source.points.size(); ++i) {
      const Vec3f& sp = source.points[i];
      const Vec3f& sn = source.normals[i];
      if (sp.z <= 0 || (sn.x == 0 && sn.y == 0 && sn.z == 0)) continue;
      const Eigen::Vector3d p = T * Eigen::Vector3d(sp.x, sp.y, sp.z);
      if (p.z() <= 0) continue;
      const int u = int(std::lround(k.fx * p.x() / p.z() + k.cx)), v = int(std::lround(k.fy * p.y() / p.z() + k.cy));
      if (u < 0 || v < 0 || u >= k.width || v >= k.height) continue;
      const Vec3f& tp = target.points[size_t(v) * k.width + u];
      const Vec3f& tn = target.normals[size_t(v) * k.width + u];
      if (tp.z <= 0 || (tn.x == 0 && tn.y == 0 && tn.z == 0)) continue;
      const Eigen::Vector3d q(tp.x, tp.y, tp.z), n(tn.x, tn.y, tn.z);
      if ((p - q).norm() > max_distance_m) continue;
      if ((R * Eigen::Vector3d(sn.x, sn.y, sn.z)).dot(n) < min_cos) continue;
      const double r = n.dot(p - q);
      // Increment on the right of T (source camera frame): p' = T (s + omega x s + v), so
      // d r / d(omega, v) = [ (s x R^T n), R^T n ].
      const Eigen::Vector3d nl = R.transpose() * n, s(sp.x, sp.y, sp.z);
      Eigen::Matrix<double, 6, 1> J;
      J << s.cross(nl), nl;
      const double huber = 0.01, w = std::fabs(r) <= huber ? 1.0 : huber / std::fabs(r);
      A += w * J * J.transpose();
      g += w * J * r;
      squared += r * r;
      ++partners;
    }
    result.partners = partners;
    result.overlap = float(partners) / float(valid_source);
    result.rmse_m = partners > 0 ? float(std::sqrt(squared / partners)) : 0.f;
    result.information = A;
    if (partners < 50) return std::nullopt;
    if (it == iterations) break;
    const Eigen::Matrix<double, 6, 1> eta = A.ldlt().solve(-g);
    if (!eta.allFinite()) return std::nullopt;
    Pose step = Pose::Identity();
    const double angle = eta.head<3>().norm();
    if (angle > 1e-12) step.linear() = Eigen::AngleAxisd(angle, eta.head<3>() / angle).toRotationMatrix();
    step.translation() = eta.tail<3>();
    T = T * step;
    if (eta.head<3>().norm() < 1e-5 && eta.tail<3>().norm() < 1e-5) {
      it = iterations - 1;  // one more pass measures the final pose's statistics
    }
  }
  result.T_target_source = T;
  return result;
}

double CloudAlignment::weakestTranslationShare() const {
  const Eigen::Matrix3d block = information.bottomRightCorner<3, 3>();
  const double trace = block.trace();
  if (!(trace > 0)) return 0;
  const Eigen::SelfAdjointEigenSolver<Eigen::Matrix3d> eigen(block);
  return std::max(0.0, eigen.eigenvalues()(0)) / trace;
}

}  // namespace vf::slam
