#include "io/triangle_bvh.h"

#include <tbb/blocked_range.h>
#include <tbb/parallel_for.h>

#include <algorithm>
#include <array>
#include <cmath>
#include <string>
#include <tuple>

#include "core/error.h"

namespace vf {
namespace {

constexpr int kLeafTriangles = 4;

Vec3f minOf(Vec3f a, Vec3f b) { return {std::min(a.x, b.x), std::min(a.y, b.y), std::min(a.z, b.z)}; }
Vec3f maxOf(Vec3f a, Vec3f b) { return {std::max(a.x, b.x), std::max(a.y, b.y), std::max(a.z, b.z)}; }
float axis(Vec3f v, int k) { return k == 0 ? v.x : k == 1 ? v.y : v.z; }

// Squared distance from p to the box [lo, hi] (0 inside).
float boxDistance2(Vec3f p, Vec3f lo, Vec3f hi) {
  const float dx = std::max({lo.x - p.x, 0.f, p.x - hi.x});
  const float dy = std::max({lo.y - p.y, 0.f, p.y - hi.y});
  const float dz = std::max({lo.z - p.z, 0.f, p.z - hi.z});
  return dx * dx + dy * dy + dz * dz;
}

}  // namespace

Vec3f closestPointOnTriangle(Vec3f p, Vec3f a, Vec3f b, Vec3f c) {
  // Ericson 5.1.5: find the Voronoi region of p (vertex, edge or face) by barycentric signs.
  const Vec3f ab = b - a, ac = c - a, ap = p - a;
  const float d1 = dot(ab, ap), d2 = dot(ac, ap);
  if (d1 <= 0.f && d2 <= 0.f) return a;
  const Vec3f bp = p - b;
  const float d3 = dot(ab, bp), d4 = dot(ac, bp);
  if (d3 >= 0.f && d4 <= d3) return b;
  const float vc = d1 * d4 - d3 * d2;
  if (vc <= 0.f && d1 >= 0.f && d3 <= 0.f) return a + ab * (d1 / (d1 - d3));
  const Vec3f cp = p - c;
  const float d5 = dot(ab, cp), d6 = dot(ac, cp);
  if (d6 >= 0.f && d5 <= d6) return c;
  const float vb = d5 * d2 - d1 * d6;
  if (vb <= 0.f && d2 >= 0.f && d6 <= 0.f) return a + ac * (d2 / (d2 - d6));
  const float va = d3 * d6 - d5 * d4;
  if (va <= 0.f && (d4 - d3) >= 0.f && (d5 - d6) >= 0.f) return b + (c - b) * ((d4 - d3) / ((d4 - d3) + (d5 - d6)));
  const float sum = va + vb + vc;
  if (!(sum > 0.f)) {
    // A sliver whose area squared underflows: its edges are the surface (the face formula would
    // divide by zero and return NaN).
    const auto onSegment = [&p](Vec3f s, Vec3f e) {
      const Vec3f d = e - s;
      const float len2 = dot(d, d);
      const float t = len2 > 0.f ? std::clamp(dot(p - s, d) / len2, 0.f, 1.f) : 0.f;
      return s + d * t;
    };
    const std::array<Vec3f, 3> q{onSegment(a, b), onSegment(b, c), onSegment(c, a)};
    const auto dist2 = [&p](Vec3f x) { return dot(p - x, p - x); };
    return *std::min_element(q.begin(), q.end(), [&](Vec3f x, Vec3f y) { return dist2(x) < dist2(y); });
  }
  const float denom = 1.f / sum;
  return a + ab * (vb * denom) + ac * (vc * denom);
}

TriangleBvh::TriangleBvh(const TriangleMesh& mesh) {
  const int32_t n = int32_t(mesh.positions.size());
  tris_.reserve(mesh.triangles.size());
  for (const auto& t : mesh.triangles) {
    for (const int32_t v : t)
      if (v < 0 || v >= n)
        throw Error("mesh triangle indexes vertex " + std::to_string(v) + " of " + std::to_string(n));
    const Tri tri{mesh.positions[size_t(t[0])], mesh.positions[size_t(t[1])], mesh.positions[size_t(t[2])]};
    if (!isFinite(tri.a) || !isFinite(tri.b) || !isFinite(tri.c)) continue;
    if (!(norm(cross(tri.b - tri.a, tri.c - tri.a)) > 0.f)) continue;  // no area, no surface
    tris_.push_back(tri);
  }
  if (tris_.empty()) throw Error("mesh has no triangle with an area (a point cloud or an empty mesh)");
  removeDuplicates();
  std::vector<Vec3f> centroids(tris_.size());
  std::vector<int> order(tris_.size());
  float magnitude = 0;
  for (size_t i = 0; i < tris_.size(); ++i) {
    centroids[i] = (tris_[i].a + tris_[i].b + tris_[i].c) * (1.f / 3.f);
    order[i] = int(i);
    for (const Vec3f& v : {tris_[i].a, tris_[i].b, tris_[i].c})
      magnitude = std::max({magnitude, std::fabs(v.x), std::fabs(v.y), std::fabs(v.z)});
  }
  // Below a millionth of the coordinates' size a distance is float rounding: a point that close
  // to a triangle lies on the surface, and the search stops there instead of visiting every
  // other triangle that passes as close (coplanar, overlapping faces).
  on_surface2_ = (magnitude * 1e-6f) * (magnitude * 1e-6f);
  nodes_.reserve(2 * tris_.size() / kLeafTriangles + 2);
  nodes_.push_back({});
  build(order, centroids, 0, 0, int(tris_.size()), 0);
  std::vector<Tri> sorted(tris_.size());
  for (size_t i = 0; i < order.size(); ++i) sorted[i] = tris_[size_t(order[i])];
  tris_ = std::move(sorted);
}

// A triangle given twice (in any corner order) is one surface: the copies would all land in one
// leaf, which no split can divide, and every query near them would test each (one triangle
// repeated 5,000 times took evaluate over a minute).
void TriangleBvh::removeDuplicates() {
  using Key = std::array<float, 9>;
  const auto key = [](const Tri& t) {
    std::array<Vec3f, 3> v{t.a, t.b, t.c};
    std::sort(v.begin(), v.end(), [](Vec3f p, Vec3f q) {
      return std::tie(p.x, p.y, p.z) < std::tie(q.x, q.y, q.z);
    });
    return Key{v[0].x, v[0].y, v[0].z, v[1].x, v[1].y, v[1].z, v[2].x, v[2].y, v[2].z};
  };
  std::vector<std::pair<Key, uint32_t>> keys(tris_.size());
  for (size_t i = 0; i < tris_.size(); ++i) keys[i] = {key(tris_[i]), uint32_t(i)};
  std::sort(keys.begin(), keys.end());
  std::vector<uint8_t> keep(tris_.size(), 0);
  for (size_t i = 0; i < keys.size(); ++i)
    if (i == 0 || keys[i].first != keys[i - 1].first) keep[keys[i].second] = 1;
  size_t kept = 0;
  for (size_t i = 0; i < tris_.size(); ++i)
    if (keep[i]) tris_[kept++] = tris_[i];
  tris_.resize(kept);
}

// Splits at the median centroid along the widest centroid axis; triangles whose centroids all
// coincide (distinct triangles about one point) are split by count. Either way each child holds
// half the triangles, so the depth stays below log2(n) + 1 and the build always ends.
void TriangleBvh::build(std::vector<int>& order, const std::vector<Vec3f>& centroids, int node, int begin, int end,
                        int depth) {
  Vec3f lo{INFINITY, INFINITY, INFINITY}, hi{-INFINITY, -INFINITY, -INFINITY};
  Vec3f clo = lo, chi = hi;
  for (int i = begin; i < end; ++i) {
    const Tri& t = tris_[size_t(order[size_t(i)])];
    lo = minOf(minOf(lo, t.a), minOf(t.b, t.c));
    hi = maxOf(maxOf(hi, t.a), maxOf(t.b, t.c));
    clo = minOf(clo, centroids[size_t(order[size_t(i)])]);
    chi = maxOf(chi, centroids[size_t(order[size_t(i)])]);
  }
  nodes_[size_t(node)].lo = lo;
  nodes_[size_t(node)].hi = hi;
  if (end - begin <= kLeafTriangles) {
    nodes_[size_t(node)].first = begin;
    nodes_[size_t(node)].count = end - begin;
    return;
  }
  if (depth + 1 >= kMaxDepth) throw Error("triangle hierarchy deeper than " + std::to_string(kMaxDepth) + " levels");
  const Vec3f extent = chi - clo;
  const int mid = begin + (end - begin) / 2;
  if (std::max({extent.x, extent.y, extent.z}) > 0.f) {
    const int k = extent.x >= extent.y && extent.x >= extent.z ? 0 : extent.y >= extent.z ? 1 : 2;
    std::nth_element(order.begin() + begin, order.begin() + mid, order.begin() + end,
                     [&](int a, int b) { return axis(centroids[size_t(a)], k) < axis(centroids[size_t(b)], k); });
  }
  const int left = int(nodes_.size());
  nodes_.push_back({});
  nodes_.push_back({});
  nodes_[size_t(node)].first = left;
  nodes_[size_t(node)].count = 0;
  build(order, centroids, left, begin, mid, depth + 1);
  build(order, centroids, left + 1, mid, end, depth + 1);
}

float TriangleBvh::distance(Vec3f p, float max_distance_m) const {
  return nearest(p, max_distance_m * max_distance_m);
}

// Branch and bound from an upper bound on the squared distance (inf: none). Stack entries carry
// their box distance so that a node is tested once.
float TriangleBvh::nearest(Vec3f p, float bound2) const {
  float best2 = bound2;
  bool found = false;
  struct Entry {
    int node;
    float d2;
  };
  Entry stack[2 * kMaxDepth];
  int top = 0;
  stack[top++] = {0, boxDistance2(p, nodes_[0].lo, nodes_[0].hi)};
  while (top > 0) {
    const Entry e = stack[--top];
    if (e.d2 >= best2) continue;
    const Node& node = nodes_[size_t(e.node)];
    if (node.count > 0) {
      for (int i = node.first; i < node.first + node.count; ++i) {
        const Tri& t = tris_[size_t(i)];
        const Vec3f d = p - closestPointOnTriangle(p, t.a, t.b, t.c);
        const float d2 = dot(d, d);
        if (d2 < best2) best2 = d2, found = true;
      }
      if (found && best2 <= on_surface2_) break;  // on the surface: nothing can be nearer by more than rounding
      continue;
    }
    // The nearer child is pushed last, visited first, so that the other is usually pruned.
    const Node& l = nodes_[size_t(node.first)];
    const Node& r = nodes_[size_t(node.first + 1)];
    const float dl = boxDistance2(p, l.lo, l.hi), dr = boxDistance2(p, r.lo, r.hi);
    if (dl < dr) {
      if (dr < best2) stack[top++] = {node.first + 1, dr};
      if (dl < best2) stack[top++] = {node.first, dl};
    } else {
      if (dl < best2) stack[top++] = {node.first, dl};
      if (dr < best2) stack[top++] = {node.first + 1, dr};
    }
  }
  return found ? std::sqrt(best2) : std::numeric_limits<float>::infinity();
}

namespace {

// 10 bits per axis interleaved: nearby points get nearby keys.
uint32_t spread10(uint32_t v) {
  v &= 0x3ff;
  v = (v | (v << 16)) & 0x030000ff;
  v = (v | (v << 8)) & 0x0300f00f;
  v = (v | (v << 4)) & 0x030c30c3;
  v = (v | (v << 2)) & 0x09249249;
  return v;
}

}  // namespace

std::vector<float> TriangleBvh::distances(const std::vector<Vec3f>& points, float max_distance_m) const {
  // Queries in Morton order: consecutive points are close, so the last answer bounds the next
  // (the distance to a surface changes by at most the distance moved) and the nodes they visit
  // are in cache.
  Vec3f lo = nodes_[0].lo, hi = nodes_[0].hi;
  for (const Vec3f& p : points)
    if (isFinite(p)) lo = minOf(lo, p), hi = maxOf(hi, p);
  const Vec3f extent = hi - lo;
  const float scale = 1023.f / std::max({extent.x, extent.y, extent.z, 1e-9f});
  std::vector<std::pair<uint32_t, uint32_t>> order(points.size());
  for (size_t i = 0; i < points.size(); ++i) {
    const Vec3f q = (points[i] - lo) * scale;
    const uint32_t key = isFinite(points[i]) ? spread10(uint32_t(q.x)) | spread10(uint32_t(q.y)) << 1 |
                                                   spread10(uint32_t(q.z)) << 2
                                             : 0;
    order[i] = {key, uint32_t(i)};
  }
  std::sort(order.begin(), order.end());
  const float max2 = max_distance_m * max_distance_m;
  std::vector<float> out(points.size());
  tbb::parallel_for(tbb::blocked_range<size_t>(0, points.size(), 1024), [&](const tbb::blocked_range<size_t>& r) {
    Vec3f last{0, 0, 0};
    float last_d = INFINITY;
    for (size_t k = r.begin(); k != r.end(); ++k) {
      const Vec3f p = points[order[k].second];
      // d(p) <= d(last) + |p - last|; a hair above it so that a triangle at exactly the bound is found.
      const float bound = (last_d + norm(p - last)) * 1.0001f + 1e-7f;
      const float bound2 = std::isfinite(bound) ? std::min(bound * bound, max2) : max2;
      float d = nearest(p, bound2);
      if (!std::isfinite(d) && bound2 < max2) d = nearest(p, max2);  // float rounding: never miss
      out[order[k].second] = d;
      if (std::isfinite(d)) last = p, last_d = d;
    }
  });
  return out;
}

}  // namespace vf
