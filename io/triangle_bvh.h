#pragma once
// Distance from points to a triangle surface (not to its vertices): a bounding-volume hierarchy
// of axis-aligned boxes over the triangles, searched branch-and-bound for the nearest one, with
// the exact point-to-triangle distance (Ericson, Real-Time Collision Detection, 5.1.5). Used by
// the surface metrics (io/mesh_metrics.h); needs no OpenVDB.
#include <cstdint>
#include <limits>
#include <vector>

#include "core/math.h"
#include "core/mesh.h"

namespace vf {

// Closest point to p on triangle (a, b, c); the triangle must have a non-zero area.
Vec3f closestPointOnTriangle(Vec3f p, Vec3f a, Vec3f b, Vec3f c);

class TriangleBvh {
 public:
  // Triangles of zero area (or with non-finite corners) carry no surface and are left out, and a
  // triangle given more than once is kept once; throws vf::Error when none is left or a triangle
  // indexes a missing vertex.
  explicit TriangleBvh(const TriangleMesh& mesh);

  size_t triangleCount() const { return tris_.size(); }
  // Distance to the nearest triangle; +infinity when none is within max_distance_m. A point within
  // a millionth of the coordinates' size of a triangle is on the surface: that distance is
  // returned without looking for a nearer one.
  float distance(Vec3f p, float max_distance_m = std::numeric_limits<float>::infinity()) const;
  // distance() for every point, in parallel.
  std::vector<float> distances(const std::vector<Vec3f>& points,
                               float max_distance_m = std::numeric_limits<float>::infinity()) const;

 private:
  struct Tri {
    Vec3f a, b, c;
  };
  struct Node {
    Vec3f lo, hi;
    int32_t first = 0;  // leaf: first triangle; inner: left child (right child = first + 1)
    int32_t count = 0;  // leaf: triangles; 0 = inner node
  };
  // Every split halves its triangles: 32 levels hold 2^31 of them (int indices allow no more).
  static constexpr int kMaxDepth = 33;
  float nearest(Vec3f p, float bound2) const;
  void removeDuplicates();
  void build(std::vector<int>& order, const std::vector<Vec3f>& centroids, int node, int begin, int end, int depth);

  std::vector<Tri> tris_;
  std::vector<Node> nodes_;
  float on_surface2_ = 0;  // squared distance below which a point is on the surface
};

}  // namespace vf
