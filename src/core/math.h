#pragma once
// Small POD vector / rigid-transform types usable in host and device code alike.
// Eigen stays on the host (pose algebra, 6x6 solves); these are what the kernels see.
#include <cmath>
#include <cstdint>

#include "core/hd.h"

namespace vf {

struct Vec3f {
  float x, y, z;
};
struct Vec2i {
  int x, y;
};
struct Vec2f {
  float x, y;
};
struct Vec3i {
  int x, y, z;
};

VF_HD Vec3f operator+(Vec3f a, Vec3f b) { return {a.x + b.x, a.y + b.y, a.z + b.z}; }
VF_HD Vec3f operator-(Vec3f a, Vec3f b) { return {a.x - b.x, a.y - b.y, a.z - b.z}; }
VF_HD Vec3f operator-(Vec3f a) { return {-a.x, -a.y, -a.z}; }
VF_HD Vec3f operator*(Vec3f a, float s) { return {a.x * s, a.y * s, a.z * s}; }
VF_HD Vec3f operator*(float s, Vec3f a) { return {a.x * s, a.y * s, a.z * s}; }
VF_HD float dot(Vec3f a, Vec3f b) { return a.x * b.x + a.y * b.y + a.z * b.z; }
VF_HD Vec3f cross(Vec3f a, Vec3f b) {
  return {a.y * b.z - a.z * b.y, a.z * b.x - a.x * b.z, a.x * b.y - a.y * b.x};
}
VF_HD float norm(Vec3f a) { return sqrtf(dot(a, a)); }
VF_HD Vec3f normalized(Vec3f a) {
  const float n = norm(a);
  return n > 0.f ? a * (1.f / n) : Vec3f{0.f, 0.f, 0.f};
}
// Host builds: <cmath> only guarantees std::isfinite (nvcc provides the global one on device).
#if !defined(__CUDACC__)
using std::isfinite;
#endif
VF_HD bool isFinite(Vec3f a) { return isfinite(a.x) && isfinite(a.y) && isfinite(a.z); }

// Rotation (row-major) plus translation: p' = R p + t. Named by the frames it maps,
// e.g. T_world_cam maps camera points into the world.
struct Rigid3f {
  float r[9];
  Vec3f t;

  VF_HD static Rigid3f identity() { return {{1, 0, 0, 0, 1, 0, 0, 0, 1}, {0, 0, 0}}; }
  VF_HD Vec3f rotate(Vec3f p) const {
    return {r[0] * p.x + r[1] * p.y + r[2] * p.z, r[3] * p.x + r[4] * p.y + r[5] * p.z,
            r[6] * p.x + r[7] * p.y + r[8] * p.z};
  }
  VF_HD Vec3f operator*(Vec3f p) const { return rotate(p) + t; }
  VF_HD Rigid3f inverse() const {
    Rigid3f inv;
    for (int i = 0; i < 3; ++i)
      for (int j = 0; j < 3; ++j) inv.r[i * 3 + j] = r[j * 3 + i];
    inv.t = -inv.rotate(t);
    return inv;
  }
};

// 8-bit RGB(A) color as stored in images and the color volume.
struct Rgb8 {
  uint8_t r, g, b, a;
};

}  // namespace vf
