#pragma once
// Data for tests of the ICP reduction alone: n measured points about 1 m in front of a camera
// (every 13th invalid), with tilted normals, against a model plane at z = 1 seen by the camera
// k. Many points find a partner, some fail the normal test: every kind of row occurs.
#include <random>
#include <vector>

#include "core/intrinsics.h"
#include "core/math.h"

namespace vf::test {

struct IcpRowsFixture {
  std::vector<Vec3f> vertex, normal;              // n measured points, camera frame
  std::vector<Vec3f> model_vertex, model_normal;  // k.width x k.height
};

inline IcpRowsFixture makeIcpRowsFixture(const Intrinsics& k, int n) {
  IcpRowsFixture f;
  std::mt19937 rng(7);
  std::uniform_real_distribution<float> ux(-0.4f, 0.4f), noise(-0.01f, 0.01f), tilt(-0.2f, 0.2f);
  f.vertex.resize(static_cast<size_t>(n));
  f.normal.resize(static_cast<size_t>(n));
  for (int i = 0; i < n; ++i) {
    const float z = 1.f + noise(rng);
    f.vertex[size_t(i)] = i % 13 == 0 ? Vec3f{0, 0, 0} : Vec3f{ux(rng) * z, ux(rng) * z, z};
    f.normal[size_t(i)] = normalized(Vec3f{tilt(rng), tilt(rng), -1.f});
  }
  f.model_vertex.resize(size_t(k.width) * k.height);
  f.model_normal.resize(f.model_vertex.size());
  for (int y = 0; y < k.height; ++y)
    for (int x = 0; x < k.width; ++x) {
      f.model_vertex[size_t(y) * k.width + x] = k.backProject(float(x), float(y), 1.f);
      f.model_normal[size_t(y) * k.width + x] = Vec3f{0.f, 0.f, -1.f};
    }
  return f;
}

}  // namespace vf::test
