#include "vdb/marching_cubes_table.h"

#include <cstddef>
#include <vector>

namespace vf {
namespace {

struct P3 {
  float x, y, z;
};
P3 corner(int c) { return {float(c & 1), float((c >> 1) & 1), float((c >> 2) & 1)}; }

int edgeBetween(int a, int b) {
  if (a > b) std::swap(a, b);
  const int diff = a ^ b;
  const int axis = diff == 1 ? 0 : diff == 2 ? 1 : 2;
  for (int e = 0; e < 12; ++e)
    if (kMcEdgeAxis[e] == axis && kMcEdgeCorner[e] == a) return e;
  return -1;
}

// Corners of each face in cyclic order.
std::array<std::array<int, 4>, 6> faceCycles() {
  std::array<std::array<int, 4>, 6> faces{};
  int f = 0;
  for (int axis = 0; axis < 3; ++axis) {
    const int u = 1 << ((axis + 1) % 3), v = 1 << ((axis + 2) % 3);
    for (int side = 0; side < 2; ++side) {
      const int base = side ? (1 << axis) : 0;
      faces[f++] = {base, base | u, base | u | v, base | v};
    }
  }
  return faces;
}

McCase buildCase(int mask) {
  auto inside = [&](int c) { return (mask >> c) & 1; };
  // Each crossing edge gets two neighbours (one per face it borders).
  std::array<std::array<int, 2>, 12> link;
  std::array<int, 12> links{};
  for (auto& l : link) l = {-1, -1};
  auto connect = [&](int a, int b) {
    link[a][links[a]++] = b;
    link[b][links[b]++] = a;
  };
  for (const auto& q : faceCycles()) {
    std::array<int, 4> edge{};
    int crossings = 0;
    for (int i = 0; i < 4; ++i) {
      edge[i] = edgeBetween(q[i], q[(i + 1) % 4]);
      crossings += inside(q[i]) != inside(q[(i + 1) % 4]);
    }
    if (crossings == 2) {
      int found[2], n = 0;
      for (int i = 0; i < 4; ++i)
        if (inside(q[i]) != inside(q[(i + 1) % 4])) found[n++] = edge[i];
      connect(found[0], found[1]);
    } else if (crossings == 4) {
      // Separate each inside corner: join the two face edges that meet at it.
      for (int i = 0; i < 4; ++i)
        if (inside(q[i])) connect(edge[(i + 3) % 4], edge[i]);
    }
  }
  McCase out;
  std::array<bool, 12> used{};
  for (int start = 0; start < 12; ++start) {
    if (used[start] || links[start] == 0) continue;
    std::vector<int> loop{start};
    used[start] = true;
    for (int prev = -1, cur = start;;) {
      const int next = link[cur][0] != prev ? link[cur][0] : link[cur][1];
      if (next == start || next < 0) break;
      loop.push_back(next);
      used[next] = true;
      prev = cur;
      cur = next;
    }
    // Orient the loop so that its normal (Newell) points from the inside corners to the outside.
    P3 area{0, 0, 0}, out_dir{0, 0, 0};
    std::vector<P3> pts;
    for (int e : loop) {
      const int a = kMcEdgeCorner[e], b = a | (1 << kMcEdgeAxis[e]);
      const P3 pa = corner(a), pb = corner(b);
      pts.push_back({(pa.x + pb.x) / 2, (pa.y + pb.y) / 2, (pa.z + pb.z) / 2});
      const float s = inside(a) ? 1.f : -1.f;  // direction inside -> outside along the edge
      out_dir = {out_dir.x + s * (pb.x - pa.x), out_dir.y + s * (pb.y - pa.y), out_dir.z + s * (pb.z - pa.z)};
    }
    for (size_t i = 0; i < pts.size(); ++i) {
      const P3 p = pts[i], q = pts[(i + 1) % pts.size()];
      area.x += (p.y - q.y) * (p.z + q.z);
      area.y += (p.z - q.z) * (p.x + q.x);
      area.z += (p.x - q.x) * (p.y + q.y);
    }
    if (area.x * out_dir.x + area.y * out_dir.y + area.z * out_dir.z < 0)
      std::vector<int>(loop.rbegin(), loop.rend()).swap(loop);
    for (size_t i = 1; i + 1 < loop.size(); ++i) {
      int8_t* t = &out.edges[size_t(out.triangle_count) * 3];
      t[0] = int8_t(loop[0]);
      t[1] = int8_t(loop[i]);
      t[2] = int8_t(loop[i + 1]);
      ++out.triangle_count;
    }
  }
  return out;
}

}  // namespace

const McCase& marchingCubesCase(int inside_mask) {
  static const std::array<McCase, 256> table = [] {
    std::array<McCase, 256> t;
    for (int m = 0; m < 256; ++m) t[m] = buildCase(m);
    return t;
  }();
  return table[inside_mask & 255];
}

}  // namespace vf
