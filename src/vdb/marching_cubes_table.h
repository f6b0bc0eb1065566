#pragma once
// Marching-cubes case table, generated at start-up from the cube's geometry instead of typed in:
// for each of the 256 inside/outside corner patterns the surface's intersection with each cube
// face is a set of segments, the segments chain into closed loops, and each loop is fanned into
// triangles. Ambiguous faces (two diagonal inside corners) always separate the inside corners;
// the choice depends only on the face's four corners, so two cubes sharing a face agree and the
// surface is watertight.
#include <array>
#include <cstddef>
#include <cstdint>

namespace vf {

// Corner c of a cube sits at offset (c & 1, (c >> 1) & 1, (c >> 2) & 1) from its lowest corner.
// Edge e runs from corner kMcEdgeCorner[e] along axis kMcEdgeAxis[e].
inline constexpr std::array<int, 12> kMcEdgeCorner = {0, 2, 4, 6, 0, 1, 4, 5, 0, 1, 2, 3};
inline constexpr std::array<int, 12> kMcEdgeAxis = {0, 0, 0, 0, 1, 1, 1, 1, 2, 2, 2, 2};

struct McCase {
  int triangle_count = 0;
  // Edge ids, three per triangle, counter-clockwise seen from the outside (positive side).
  std::array<int8_t, 36> edges{};
};

// `inside_mask` has bit c set when corner c is inside (value below the iso level).
const McCase& marchingCubesCase(int inside_mask);

}  // namespace vf
