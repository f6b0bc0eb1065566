#pragma once
// The room's known surface as a triangle mesh (world frame of groundtruth.txt, metres), with
// outward normals and the texture's colours at the vertices. Box faces are exact; spheres and
// cylinders deviate from the true surface by at most 0.5 mm. Faces hidden against other solids
// (a box's underside on the floor) are kept: no camera sees them, so they never count as seen.
#include <vector>

#include "core/mesh.h"
#include "room_geometry.h"

namespace vf::synth {

// Triangles no longer than about `max_edge_m` (so that a per-vertex colour shows the texture).
// `triangle_primitive`, when given, receives the primitive index of every triangle.
TriangleMesh groundTruthMesh(const Room& room, float max_edge_m = 0.05f, std::vector<int>* triangle_primitive = nullptr);

// The mesh without the triangles of primitive `left_out` (for tests of the completion metric).
TriangleMesh meshWithout(const TriangleMesh& mesh, const std::vector<int>& triangle_primitive, int left_out);

}  // namespace vf::synth
