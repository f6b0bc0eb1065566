#pragma once
#include "core/math.h"

namespace vf {

// Pinhole camera. Pixel (u, v) of a point p in camera coordinates (z forward, metres):
// u = fx * x / z + cx, v = fy * y / z + cy.
struct Intrinsics {
  float fx = 0, fy = 0, cx = 0, cy = 0;
  int width = 0, height = 0;

  VF_HD Vec3f backProject(float u, float v, float depth_m) const {
    return {(u - cx) * depth_m / fx, (v - cy) * depth_m / fy, depth_m};
  }
  VF_HD bool project(Vec3f p, float& u, float& v) const {
    if (p.z <= 0.f) return false;
    projectAnyDepth(p, u, v);
    return true;
  }
  // project() without the z > 0 test, for loops that must stay branch-free to vectorise: u and v
  // mean nothing where p.z <= 0, and the caller tests p.z itself.
  VF_HD void projectAnyDepth(Vec3f p, float& u, float& v) const {
    u = fx * p.x / p.z + cx;
    v = fy * p.y / p.z + cy;
  }
  // The camera of an image downsampled by 2^level (pixel centres stay consistent).
  Intrinsics atLevel(int level) const {
    Intrinsics k = *this;
    const float s = 1.f / float(1 << level);
    k.fx = fx * s;
    k.fy = fy * s;
    k.cx = (cx + 0.5f) * s - 0.5f;
    k.cy = (cy + 0.5f) * s - 0.5f;
    k.width = width >> level;
    k.height = height >> level;
    return k;
  }
  bool valid() const { return fx > 0 && fy > 0 && width > 0 && height > 0; }
};

// Radial-tangential (OpenCV / Brown) distortion, k1 k2 p1 p2 k3; all zero for undistorted input.
struct Distortion {
  float k1 = 0, k2 = 0, p1 = 0, p2 = 0, k3 = 0;
  bool isZero() const { return k1 == 0 && k2 == 0 && p1 == 0 && p2 == 0 && k3 == 0; }
};

}  // namespace vf
