#include "io/mesh_metrics.h"

#include <tbb/blocked_range.h>
#include <tbb/parallel_for.h>

#include <algorithm>
#include <cmath>

#include "core/error.h"

namespace vf {
namespace {

uint64_t splitmix64(uint64_t x) {
  x += 0x9E3779B97F4A7C15ull;
  x = (x ^ (x >> 30)) * 0xBF58476D1CE4E5B9ull;
  x = (x ^ (x >> 27)) * 0x94D049BB133111EBull;
  return x ^ (x >> 31);
}

// Uniform in [0, 1) from 53 random bits.
double unit(uint64_t bits) { return double(bits >> 11) * (1.0 / 9007199254740992.0); }

double triangleArea(const TriangleMesh& m, const std::array<int32_t, 3>& t) {
  const Vec3f a = m.positions[size_t(t[0])], b = m.positions[size_t(t[1])], c = m.positions[size_t(t[2])];
  const double area = 0.5 * double(norm(cross(b - a, c - a)));
  return std::isfinite(area) ? area : 0.0;
}

void checkIndices(const TriangleMesh& m) {
  for (const auto& t : m.triangles)
    for (const int32_t v : t)
      if (v < 0 || size_t(v) >= m.positions.size())
        throw Error("mesh triangle indexes vertex " + std::to_string(v) + " of " + std::to_string(m.positions.size()));
}

struct Stats {
  double median = 0, mean = 0, within = 0;
};

Stats statsOf(const std::vector<float>& d, double threshold) {
  std::vector<float> finite;
  finite.reserve(d.size());
  size_t within = 0;
  for (const float v : d) {
    if (std::isfinite(v)) finite.push_back(v);
    if (v <= threshold) ++within;
  }
  Stats s;
  s.within = double(within) / double(d.size());
  if (finite.empty()) return {INFINITY, INFINITY, s.within};
  double sum = 0;
  for (const float v : finite) sum += v;
  s.mean = sum / double(finite.size());
  std::nth_element(finite.begin(), finite.begin() + finite.size() / 2, finite.end());
  s.median = finite[finite.size() / 2];
  return s;
}

}  // namespace

double surfaceArea(const TriangleMesh& mesh) {
  checkIndices(mesh);
  double area = 0;
  for (const auto& t : mesh.triangles) area += triangleArea(mesh, t);
  return area;
}

std::vector<Vec3f> sampleSurface(const TriangleMesh& mesh, size_t count, uint64_t seed) {
  checkIndices(mesh);
  std::vector<double> cumulative(mesh.triangles.size());
  double total = 0;
  for (size_t i = 0; i < mesh.triangles.size(); ++i) cumulative[i] = total += triangleArea(mesh, mesh.triangles[i]);
  if (!(total > 0)) throw Error("mesh has no surface to sample (no triangle with an area)");
  // Systematic sampling: sample k sits at area (k + u0) * total / count along the triangles, so
  // each triangle gets its area's share (rounded up or down) and one sweep finds them all.
  const double u0 = unit(splitmix64(seed)), step = total / double(count);
  std::vector<Vec3f> points(count);
  tbb::parallel_for(tbb::blocked_range<size_t>(0, count, 16384), [&](const tbb::blocked_range<size_t>& r) {
    size_t t = size_t(std::upper_bound(cumulative.begin(), cumulative.end(), (double(r.begin()) + u0) * step) -
                      cumulative.begin());
    for (size_t k = r.begin(); k != r.end(); ++k) {
      const double at = (double(k) + u0) * step;
      while (t + 1 < cumulative.size() && cumulative[t] <= at) ++t;
      // Where on the triangle: two numbers from (seed, k), the same whatever the thread split.
      const uint64_t h = splitmix64(seed ^ splitmix64(k + 1));
      const double r1 = std::sqrt(unit(h)), r2 = unit(splitmix64(h));
      const auto& tri = mesh.triangles[t];
      const Vec3f a = mesh.positions[size_t(tri[0])], b = mesh.positions[size_t(tri[1])],
                  c = mesh.positions[size_t(tri[2])];
      // Uniform on the triangle (Osada et al. 2002): (1 - sqrt r1) a + sqrt r1 (1 - r2) b + sqrt r1 r2 c.
      points[k] = a * float(1 - r1) + b * float(r1 * (1 - r2)) + c * float(r1 * r2);
    }
  });
  return points;
}

TriangleMesh transformMesh(const TriangleMesh& mesh, const Pose& T) {
  TriangleMesh out = mesh;
  const Eigen::Matrix3d R = T.linear();
  for (Vec3f& p : out.positions) {
    const Eigen::Vector3d q = T * Eigen::Vector3d(p.x, p.y, p.z);
    p = {float(q.x()), float(q.y()), float(q.z())};
  }
  for (Vec3f& n : out.normals) {
    const Eigen::Vector3d q = R * Eigen::Vector3d(n.x, n.y, n.z);
    n = {float(q.x()), float(q.y()), float(q.z())};
  }
  return out;
}

void markSeen(const std::vector<Vec3f>& points, const ViewCamera& camera, std::vector<uint8_t>& seen) {
  if (seen.size() != points.size()) throw Error("markSeen: seen must have one entry per point");
  const Intrinsics& k = camera.intrinsics;
  if (camera.depth && (camera.depth->width() != k.width || camera.depth->height() != k.height))
    throw Error("markSeen: the depth map is not the size of the intrinsics");
  const Rigid3f T_cam_world = toRigid3f(camera.T_world_cam.inverse());
  tbb::parallel_for(tbb::blocked_range<size_t>(0, points.size(), 8192), [&](const tbb::blocked_range<size_t>& r) {
    for (size_t i = r.begin(); i != r.end(); ++i) {
      if (seen[i]) continue;
      const Vec3f p = T_cam_world.rotate(points[i]) + T_cam_world.t;
      if (!(p.z >= camera.min_depth_m && p.z <= camera.max_depth_m)) continue;
      float u = 0, v = 0;
      if (!k.project(p, u, v)) continue;
      const long x = std::lround(u), y = std::lround(v);
      if (x < 0 || y < 0 || x >= k.width || y >= k.height) continue;
      if (camera.depth) {
        const float d = (*camera.depth)(int(x), int(y));
        if (!(d > 0.f) || p.z > d + camera.occlusion_tolerance_m) continue;
      }
      seen[i] = 1;
    }
  });
}

SurfaceMetrics surfaceMetrics(const std::vector<float>& rec_to_ref, const std::vector<float>& ref_to_rec,
                              double threshold_m) {
  if (rec_to_ref.empty()) throw Error("surface metrics: no reconstructed points");
  if (ref_to_rec.empty()) throw Error("surface metrics: no reference points (none seen by the trajectory?)");
  SurfaceMetrics m;
  m.threshold_m = threshold_m;
  m.reconstruction_points = rec_to_ref.size();
  m.reference_points = ref_to_rec.size();
  const Stats acc = statsOf(rec_to_ref, threshold_m), comp = statsOf(ref_to_rec, threshold_m);
  m.accuracy_median_m = acc.median, m.accuracy_mean_m = acc.mean;
  m.completion_median_m = comp.median, m.completion_mean_m = comp.mean;
  m.precision = acc.within;
  m.completion_ratio = comp.within;
  m.fscore = m.precision + m.completion_ratio > 0
                 ? 2 * m.precision * m.completion_ratio / (m.precision + m.completion_ratio)
                 : 0.0;
  return m;
}

}  // namespace vf
