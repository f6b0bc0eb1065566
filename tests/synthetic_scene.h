#pragma once
// Analytic scenes rendered to exact depth maps, for tests with known answers: planes and
// spheres, ray-intersected per pixel from any camera pose.
#include <cmath>
#include <functional>
#include <limits>
#include <vector>

#include "core/frame.h"

namespace vf::test {

struct Plane {
  Eigen::Vector3d normal;  // unit
  double offset;           // points x with normal.x = offset
};
struct Sphere {
  Eigen::Vector3d center;
  double radius;
};

struct SyntheticScene {
  std::vector<Plane> planes;
  std::vector<Sphere> spheres;
  // The colour at a surface point; empty: sinusoids of the world coordinates.
  std::function<Rgb8(const Eigen::Vector3d&)> color_at;

  // Distance along the unit ray to the first surface, or +inf.
  double intersect(const Eigen::Vector3d& origin, const Eigen::Vector3d& dir) const {
    double best = std::numeric_limits<double>::infinity();
    for (const Plane& p : planes) {
      const double denom = p.normal.dot(dir);
      if (std::abs(denom) < 1e-9) continue;
      const double t = (p.offset - p.normal.dot(origin)) / denom;
      if (t > 1e-6 && t < best) best = t;
    }
    for (const Sphere& s : spheres) {
      const Eigen::Vector3d oc = origin - s.center;
      const double b = oc.dot(dir), c = oc.squaredNorm() - s.radius * s.radius;
      const double disc = b * b - c;
      if (disc < 0) continue;
      const double t = -b - std::sqrt(disc);
      if (t > 1e-6 && t < best) best = t;
    }
    return best;
  }

  // Depth (z, metres) and a position-dependent color seen by a camera at T_world_cam.
  RgbdFrame render(const Intrinsics& k, const Pose& T_world_cam, double max_depth_m = 4.0) const {
    RgbdFrame frame;
    frame.depth.resize(k.width, k.height, 0.f);
    frame.color.resize(k.width, k.height, Rgb8{0, 0, 0, 255});
    for (int y = 0; y < k.height; ++y)
      for (int x = 0; x < k.width; ++x) {
        const Eigen::Vector3d ray_cam((x - k.cx) / k.fx, (y - k.cy) / k.fy, 1.0);
        const Eigen::Vector3d dir = T_world_cam.linear() * ray_cam.normalized();
        const double t = intersect(T_world_cam.translation(), dir);
        const double z = t / ray_cam.norm();
        if (!std::isfinite(t) || z > max_depth_m) continue;
        frame.depth(x, y) = float(z);
        const Eigen::Vector3d p = T_world_cam.translation() + t * dir;
        frame.color(x, y) = color_at ? color_at(p)
                                     : Rgb8{uint8_t(128 + 100 * std::sin(20 * p.x())),
                                            uint8_t(128 + 100 * std::sin(20 * p.y())),
                                            uint8_t(128 + 100 * std::sin(20 * p.z())), 255};
      }
    return frame;
  }
};

inline Intrinsics testCamera(int width = 320, int height = 240) {
  Intrinsics k;
  k.width = width;
  k.height = height;
  k.fx = k.fy = 0.8f * float(width);
  k.cx = 0.5f * float(width) - 0.5f;
  k.cy = 0.5f * float(height) - 0.5f;
  return k;
}

// A corner of a room (floor, back wall, side wall) with two balls: constrains all six DoF.
inline SyntheticScene roomCorner() {
  SyntheticScene s;
  s.planes.push_back({Eigen::Vector3d(0, 0, -1), -1.6});           // back wall z = 1.6
  s.planes.push_back({Eigen::Vector3d(0, -1, 0), -0.45});          // floor y = 0.45
  s.planes.push_back({Eigen::Vector3d(1, 0, 0), -0.6});            // side wall x = -0.6
  s.spheres.push_back({Eigen::Vector3d(0.1, 0.2, 1.1), 0.22});
  s.spheres.push_back({Eigen::Vector3d(-0.3, 0.3, 1.3), 0.15});
  return s;
}

inline Pose poseFrom(double rx_deg, double ry_deg, double rz_deg, double tx, double ty, double tz) {
  const double d = M_PI / 180.0;
  Pose p = Pose::Identity();
  p.linear() = (Eigen::AngleAxisd(rz_deg * d, Eigen::Vector3d::UnitZ()) *
                Eigen::AngleAxisd(ry_deg * d, Eigen::Vector3d::UnitY()) *
                Eigen::AngleAxisd(rx_deg * d, Eigen::Vector3d::UnitX()))
                   .toRotationMatrix();
  p.translation() = Eigen::Vector3d(tx, ty, tz);
  return p;
}

}  // namespace vf::test
