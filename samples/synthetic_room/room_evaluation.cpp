#include "room_evaluation.h"

#include <tbb/parallel_for.h>
#include <tbb/parallel_sort.h>

#include <algorithm>
#include <atomic>
#include <cmath>
#include <limits>

#include "core/error.h"
#include "io/trajectory_metrics.h"
#include "room_render.h"

namespace vf::synth {
namespace {

constexpr int kPatchSide = 32;  // grid points per patch edge
constexpr float kHiddenOffset_m = 0.002f, kHiddenMargin_m = 0.001f;
constexpr float kOcclusionTolerance_m = 0.002f;

struct SampleBuilder {
  SurfaceSamples& out;
  int primitive = 0;

  void beginPatch() { out.patches.push_back({out.points.size(), out.points.size(), Vec3::Zero(), Vec3::Zero()}); }
  void add(const Vec3& p, const Vec3& n) {
    out.points.push_back(p);
    out.normals.push_back(n);
    out.primitive.push_back(primitive);
    out.patches.back().end = out.points.size();
  }
  // Cell centres of an n1 x n2 grid over corner + s e1 + t e2, in patches of kPatchSide^2.
  void grid(const Vec3& corner, const Vec3& e1, const Vec3& e2, const Vec3& normal, float spacing) {
    const int n1 = std::max(1, int(std::lround(e1.norm() / spacing))), n2 = std::max(1, int(std::lround(e2.norm() / spacing)));
    for (int j0 = 0; j0 < n2; j0 += kPatchSide)
      for (int i0 = 0; i0 < n1; i0 += kPatchSide) {
        beginPatch();
        for (int j = j0; j < std::min(n2, j0 + kPatchSide); ++j)
          for (int i = i0; i < std::min(n1, i0 + kPatchSide); ++i)
            add(corner + e1 * ((float(i) + 0.5f) / float(n1)) + e2 * ((float(j) + 0.5f) / float(n2)), normal);
      }
  }
  void box(const Primitive& p, bool inward, float spacing) {
    for (int a = 0; a < 3; ++a)
      for (int side = 0; side < 2; ++side) {
        Vec3 corner = p.lo;
        corner[a] = side ? p.hi[a] : p.lo[a];
        Vec3 e1 = Vec3::Zero(), e2 = Vec3::Zero();
        e1[(a + 1) % 3] = p.hi[(a + 1) % 3] - p.lo[(a + 1) % 3];
        e2[(a + 2) % 3] = p.hi[(a + 2) % 3] - p.lo[(a + 2) % 3];
        Vec3 normal = Vec3::Zero();
        normal[a] = (side == 1) != inward ? 1.f : -1.f;
        grid(corner, e1, e2, normal, spacing);
      }
  }
  void sphere(const Primitive& p, float spacing) {
    const int n = std::max(16, int(std::lround(4 * M_PI * p.radius * p.radius / (spacing * spacing))));
    const float golden = float(M_PI) * (3.f - std::sqrt(5.f));
    for (int i = 0; i < n; ++i) {
      if (i % (kPatchSide * kPatchSide / 4) == 0) beginPatch();  // latitude bands
      const float z = 1.f - 2.f * (float(i) + 0.5f) / float(n), r = std::sqrt(std::max(0.f, 1.f - z * z));
      const Vec3 d(r * std::cos(golden * float(i)), r * std::sin(golden * float(i)), z);
      add(p.center + p.radius * d, d);
    }
  }
  void cylinder(const Primitive& p, float spacing) {
    const float h = p.hi.z() - p.lo.z();
    const int na = std::max(8, int(std::lround(2 * M_PI * p.radius / spacing))), nz = std::max(1, int(std::lround(h / spacing)));
    for (int k0 = 0; k0 < nz; k0 += kPatchSide)
      for (int j0 = 0; j0 < na; j0 += kPatchSide) {
        beginPatch();
        for (int k = k0; k < std::min(nz, k0 + kPatchSide); ++k)
          for (int j = j0; j < std::min(na, j0 + kPatchSide); ++j) {
            const float phi = 2.f * float(M_PI) * (float(j) + 0.5f) / float(na);
            const Vec3 radial(std::cos(phi), std::sin(phi), 0);
            add(Vec3(p.center.x(), p.center.y(), p.lo.z() + h * (float(k) + 0.5f) / float(nz)) + p.radius * radial, radial);
          }
      }
    const int nc = std::max(1, int(std::lround(2 * p.radius / spacing)));
    for (int top = 0; top < 2; ++top) {
      beginPatch();
      for (int j = 0; j < nc; ++j)
        for (int i = 0; i < nc; ++i) {
          const float x = -p.radius + 2 * p.radius * (float(i) + 0.5f) / float(nc);
          const float y = -p.radius + 2 * p.radius * (float(j) + 0.5f) / float(nc);
          if (x * x + y * y > p.radius * p.radius) continue;
          add(Vec3(p.center.x() + x, p.center.y() + y, top ? p.hi.z() : p.lo.z()), Vec3(0, 0, top ? 1.f : -1.f));
        }
    }
  }
};

// Keeps the samples `keep` marks, patch by patch, and recomputes the patches' bounds.
SurfaceSamples compact(const SurfaceSamples& in, const std::vector<uint8_t>& keep) {
  SurfaceSamples out;
  for (const SurfaceSamples::Patch& patch : in.patches) {
    SurfaceSamples::Patch q{out.points.size(), out.points.size(), Vec3::Constant(std::numeric_limits<float>::max()),
                            Vec3::Constant(-std::numeric_limits<float>::max())};
    for (size_t i = patch.begin; i < patch.end; ++i) {
      if (!keep[i]) continue;
      out.points.push_back(in.points[i]);
      out.normals.push_back(in.normals[i]);
      out.primitive.push_back(in.primitive[i]);
      q.lo = q.lo.cwiseMin(in.points[i]);
      q.hi = q.hi.cwiseMax(in.points[i]);
    }
    q.end = out.points.size();
    if (q.end > q.begin) out.patches.push_back(q);
  }
  return out;
}

// Closest point of triangle abc to p (Ericson, Real-Time Collision Detection, 5.1.5).
Vec3 closestOnTriangle(const Vec3& p, const Vec3& a, const Vec3& b, const Vec3& c) {
  const Vec3 ab = b - a, ac = c - a, ap = p - a;
  const float d1 = ab.dot(ap), d2 = ac.dot(ap);
  if (d1 <= 0 && d2 <= 0) return a;
  const Vec3 bp = p - b;
  const float d3 = ab.dot(bp), d4 = ac.dot(bp);
  if (d3 >= 0 && d4 <= d3) return b;
  const float vc = d1 * d4 - d3 * d2;
  if (vc <= 0 && d1 >= 0 && d3 <= 0) return a + ab * (d1 / (d1 - d3));
  const Vec3 cp = p - c;
  const float d5 = ab.dot(cp), d6 = ac.dot(cp);
  if (d6 >= 0 && d5 <= d6) return c;
  const float vb = d5 * d2 - d1 * d6;
  if (vb <= 0 && d2 >= 0 && d6 <= 0) return a + ac * (d2 / (d2 - d6));
  const float va = d3 * d6 - d5 * d4;
  if (va <= 0 && (d4 - d3) >= 0 && (d5 - d6) >= 0) return b + (c - b) * ((d4 - d3) / ((d4 - d3) + (d5 - d6)));
  const float denom = va + vb + vc;
  if (!(std::abs(denom) > 0)) return a;  // degenerate triangle
  const float v = vb / denom, w = vc / denom;
  return a + ab * v + ac * w;
}

uint64_t cellKey(int64_t x, int64_t y, int64_t z) {
  constexpr int64_t kOffset = int64_t(1) << 20;  // +-1 million cells per axis
  return (uint64_t(x + kOffset) << 42) | (uint64_t(y + kOffset) << 21) | uint64_t(z + kOffset);
}

}  // namespace

SurfaceSamples sampleSurface(const Room& room, float spacing_m) {
  if (!(spacing_m >= 0.001f && spacing_m <= 1.f))
    throw Error("synthetic room: sample spacing " + std::to_string(spacing_m) + " m is outside 0.001..1 m");
  SurfaceSamples all;
  SampleBuilder b{all};
  for (size_t i = 0; i < room.primitives.size(); ++i) {
    const Primitive& p = room.primitives[i];
    b.primitive = int(i);
    switch (p.kind) {
      case Primitive::Kind::kBox: b.box(p, false, spacing_m); break;
      case Primitive::Kind::kShell: b.box(p, true, spacing_m); break;
      case Primitive::Kind::kSphere: b.sphere(p, spacing_m); break;
      case Primitive::Kind::kCylinder: b.cylinder(p, spacing_m); break;
    }
  }
  // A point just off the surface inside another solid is on a face no camera can see.
  std::vector<uint8_t> keep(all.size(), 1);
  tbb::parallel_for(size_t(0), all.size(), [&](size_t i) {
    keep[i] = !room.insideSolid(all.points[i] + kHiddenOffset_m * all.normals[i], all.primitive[i], kHiddenMargin_m);
  });
  return compact(all, keep);
}

std::vector<uint8_t> markSeen(const Room& room, const SurfaceSamples& samples, const Trajectory& path,
                              const Intrinsics& k, const SeenOptions& options) {
  struct Camera {
    Eigen::Matrix3f R_cam_world;
    Vec3 origin;
    Frustum frustum;
    TileCuller culler;
  };
  std::vector<Camera> cameras;
  cameras.reserve(path.size());
  for (const StampedPose& pose : path)
    cameras.push_back({pose.T_world_cam.linear().transpose().cast<float>(), pose.T_world_cam.translation().cast<float>(),
                       pixelFrustum(k, pose.T_world_cam, -0.5f, float(k.width) - 0.5f, -0.5f, float(k.height) - 0.5f),
                       TileCuller(room, k, pose.T_world_cam)});
  const float min_cos = std::cos(options.max_incidence_deg * float(M_PI) / 180.f);
  std::vector<uint8_t> seen(samples.size(), 0);
  tbb::parallel_for(size_t(0), samples.patches.size(), [&](size_t pi) {
    const SurfaceSamples::Patch& patch = samples.patches[pi];
    for (const Camera& cam : cameras) {
      if (!cam.frustum.meetsBox(patch.lo, patch.hi, options.min_depth_m, options.max_depth_m)) continue;
      for (size_t i = patch.begin; i < patch.end; ++i) {
        if (seen[i]) continue;
        const Vec3 q = cam.R_cam_world * (samples.points[i] - cam.origin);
        if (q.z() < options.min_depth_m || q.z() > options.max_depth_m) continue;
        const float u = k.fx * q.x() / q.z() + k.cx, v = k.fy * q.y() / q.z() + k.cy;
        const int px = int(std::floor(u + 0.5f)), py = int(std::floor(v + 0.5f));
        if (px < 0 || py < 0 || px >= k.width || py >= k.height) continue;
        const Vec3 to_point = samples.points[i] - cam.origin;
        const float distance = to_point.norm();
        const Vec3 dir = to_point / distance;
        if (-samples.normals[i].dot(dir) < min_cos) continue;  // grazing or facing away
        Hit hit;
        if (room.intersect(cam.origin, dir, distance - kOcclusionTolerance_m, hit, &cam.culler.candidates(px, py))) continue;
        seen[i] = 1;
      }
    }
  });
  return seen;
}

TriangleIndex::TriangleIndex(const TriangleMesh& mesh, float cell_m) : cell_m_(cell_m) {
  if (mesh.triangles.empty()) throw Error("mesh has no triangles to measure distances to");
  if (!(cell_m > 0)) throw Error("triangle index: cell size must be positive");
  const size_t n = mesh.triangles.size();
  a_.resize(n);
  b_.resize(n);
  c_.resize(n);
  for (size_t t = 0; t < n; ++t) {
    Vec3* corners[3] = {&a_[t], &b_[t], &c_[t]};
    for (int e = 0; e < 3; ++e) {
      const int32_t v = mesh.triangles[t][size_t(e)];
      if (v < 0 || size_t(v) >= mesh.positions.size())
        throw Error("mesh triangle " + std::to_string(t) + " names vertex " + std::to_string(v) + " of " +
                    std::to_string(mesh.positions.size()));
      *corners[e] = Vec3(mesh.positions[size_t(v)].x, mesh.positions[size_t(v)].y, mesh.positions[size_t(v)].z);
    }
  }
  // Cells whose centre is within half a cell diagonal of the triangle's plane, inside its bounds.
  const float half_diagonal = 0.8660254f * cell_m;
  for (size_t t = 0; t < n; ++t) {
    const Vec3 lo = a_[t].cwiseMin(b_[t]).cwiseMin(c_[t]), hi = a_[t].cwiseMax(b_[t]).cwiseMax(c_[t]);
    if (!lo.allFinite() || !hi.allFinite()) continue;
    if (lo.minCoeff() < -1e4f || hi.maxCoeff() > 1e4f)
      throw Error("mesh triangle " + std::to_string(t) + " lies more than 10 km from the origin");
    Vec3 normal = (b_[t] - a_[t]).cross(c_[t] - a_[t]);
    const float area2 = normal.norm();
    normal = area2 > 0 ? Vec3(normal / area2) : Vec3::Zero();
    const Eigen::Vector3i c0 = (lo / cell_m).array().floor().cast<int>(), c1 = (hi / cell_m).array().floor().cast<int>();
    for (int z = c0.z(); z <= c1.z(); ++z)
      for (int y = c0.y(); y <= c1.y(); ++y)
        for (int x = c0.x(); x <= c1.x(); ++x) {
          const Vec3 centre = (Vec3(float(x), float(y), float(z)) + Vec3::Constant(0.5f)) * cell_m;
          if (area2 > 0 && std::abs(normal.dot(centre - a_[t])) > half_diagonal) continue;
          entries_.push_back({cellKey(x, y, z), uint32_t(t)});
        }
  }
  tbb::parallel_sort(entries_.begin(), entries_.end());
}

float TriangleIndex::nearestWithin(const Vec3& p, float radius) const {
  const Eigen::Vector3i c0 = ((p - Vec3::Constant(radius)) / cell_m_).array().floor().cast<int>();
  const Eigen::Vector3i c1 = ((p + Vec3::Constant(radius)) / cell_m_).array().floor().cast<int>();
  float best2 = radius * radius;
  bool found = false;
  for (int z = c0.z(); z <= c1.z(); ++z)
    for (int y = c0.y(); y <= c1.y(); ++y)
      for (int x = c0.x(); x <= c1.x(); ++x) {
        const uint64_t key = cellKey(x, y, z);
        auto it = std::lower_bound(entries_.begin(), entries_.end(), std::make_pair(key, uint32_t(0)));
        for (; it != entries_.end() && it->first == key; ++it) {
          const uint32_t t = it->second;
          const float d2 = (closestOnTriangle(p, a_[t], b_[t], c_[t]) - p).squaredNorm();
          if (d2 <= best2) {
            best2 = d2;
            found = true;
          }
        }
      }
  return found ? std::sqrt(best2) : std::numeric_limits<float>::infinity();
}

SurfaceScores scoreReconstruction(const Room& room, const SurfaceSamples& samples, const std::vector<uint8_t>& seen,
                                  const TriangleMesh& reconstruction, float threshold_m) {
  if (seen.size() != samples.size()) throw Error("seen flags and surface samples differ in number");
  SurfaceScores s;
  s.threshold_m = threshold_m;
  s.samples = samples.size();
  s.by_primitive.assign(room.primitives.size(), {0, 0});
  const TriangleIndex index(reconstruction, threshold_m);
  std::vector<uint8_t> complete(samples.size(), 0);
  tbb::parallel_for(size_t(0), samples.size(), [&](size_t i) {
    if (seen[i]) complete[i] = index.nearestWithin(samples.points[i], threshold_m) <= threshold_m;
  });
  for (size_t i = 0; i < samples.size(); ++i) {
    if (!seen[i]) continue;
    ++s.seen;
    s.complete += complete[i];
    auto& per = s.by_primitive[size_t(samples.primitive[i])];
    ++per.first;
    per.second += complete[i];
  }
  if (s.seen == 0) throw Error("no point of the room's surface was seen by the path");
  s.completion = double(s.complete) / double(s.seen);

  // Accuracy over the vertices that belong to a triangle.
  std::vector<uint8_t> used(reconstruction.positions.size(), 0);
  for (const auto& t : reconstruction.triangles)
    for (int32_t v : t) used[size_t(v)] = 1;
  std::vector<size_t> which;
  for (size_t v = 0; v < used.size(); ++v)
    if (used[v]) which.push_back(v);
  std::vector<float> distances(which.size());
  tbb::parallel_for(size_t(0), which.size(), [&](size_t i) {
    const Vec3f& p = reconstruction.positions[which[i]];
    distances[i] = room.distanceToSurface(Vec3(p.x, p.y, p.z));
  });
  s.vertices = distances.size();
  double sum = 0;
  size_t within = 0;
  for (float d : distances) {
    sum += d;
    within += d <= threshold_m;
  }
  s.accuracy_mean_m = sum / double(distances.size());
  std::nth_element(distances.begin(), distances.begin() + long(distances.size() / 2), distances.end());
  s.accuracy_median_m = distances[distances.size() / 2];
  // Nearest rank: the smallest distance at least 90 % of the vertices are within.
  const size_t p90 = (9 * distances.size() + 9) / 10 - 1;  // ceil(0.9 n) - 1
  std::nth_element(distances.begin(), distances.begin() + long(p90), distances.end());
  s.accuracy_p90_m = distances[p90];
  s.precision = double(within) / double(distances.size());
  s.fscore = s.precision + s.completion > 0 ? 2 * s.precision * s.completion / (s.precision + s.completion) : 0;
  return s;
}

Alignment parseAlignment(const std::string& name) {
  if (name == "none") return Alignment::kNone;
  if (name == "first") return Alignment::kFirstPose;
  if (name == "ate") return Alignment::kAte;
  throw Error("alignment '" + name + "': expected none, first or ate");
}

Pose alignTo(const Trajectory& estimate, const Trajectory& ground_truth, Alignment alignment) {
  switch (alignment) {
    case Alignment::kNone: return Pose::Identity();
    case Alignment::kAte: return computeAte(estimate, ground_truth).T_gt_est;
    case Alignment::kFirstPose: {
      for (const StampedPose& e : estimate) {
        const auto gt = poseNearTimestamp(ground_truth, e.timestamp);
        if (gt) return *gt * e.T_world_cam.inverse();
      }
      throw Error("no estimated pose has a ground-truth pose within " + std::to_string(kTumMaxTimeDifference_s) + " s");
    }
  }
  return Pose::Identity();
}

TriangleMesh transformed(const TriangleMesh& mesh, const Pose& T) {
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

}  // namespace vf::synth
