#pragma once
// Which faces of a triangle mesh share an edge: what charts grow along and what the bake shares
// its frame choices across.
#include <array>
#include <cstdint>
#include <vector>

#include "core/mesh.h"

namespace vf {

// Per face, the face across each of its edges (corner k to k+1), or -1. An edge of more than
// two faces joins only the first two.
std::vector<std::array<int32_t, 3>> edgeNeighbours(const TriangleMesh& mesh);

}  // namespace vf
