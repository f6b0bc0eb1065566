#include "texture/mesh_adjacency.h"

#include <algorithm>
#include <unordered_map>
#include <utility>

namespace vf {

std::vector<std::array<int32_t, 3>> edgeNeighbours(const TriangleMesh& mesh) {
  std::vector<std::array<int32_t, 3>> nb(mesh.triangleCount(), {-1, -1, -1});
  std::unordered_map<uint64_t, std::pair<int32_t, int>> open;  // edge -> (face, corner) seen once
  open.reserve(mesh.triangleCount() * 2);
  for (size_t f = 0; f < mesh.triangleCount(); ++f) {
    for (int k = 0; k < 3; ++k) {
      const uint32_t a = uint32_t(mesh.triangles[f][size_t(k)]), b = uint32_t(mesh.triangles[f][size_t((k + 1) % 3)]);
      const uint64_t key = (uint64_t(std::min(a, b)) << 32) | std::max(a, b);
      auto [it, inserted] = open.emplace(key, std::make_pair(int32_t(f), k));
      if (inserted) continue;
      if (it->second.first >= 0) {
        nb[f][size_t(k)] = it->second.first;
        nb[size_t(it->second.first)][size_t(it->second.second)] = int32_t(f);
        it->second.first = -1;  // a third face on this edge stays apart
      }
    }
  }
  return nb;
}

}  // namespace vf
