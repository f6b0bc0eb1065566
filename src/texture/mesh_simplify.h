#pragma once
// Fewer triangles for the same shape: edge collapses under a quadric error bound (meshoptimizer's
// meshopt_simplify, Garland & Heckbert 1997). Planar walls become a few large triangles; edges
// and small objects keep their shape because collapsing across them costs error.
#include <cstddef>

#include "core/mesh.h"

namespace vf {

struct SimplifyOptions {
  size_t target_triangles = 200000;  // stop once at or under this many
  // Never move the surface further than this (metres): where the bound is reached first the
  // result keeps more triangles than asked for. 0 = no bound but the target.
  float max_error_m = 0.02f;
};

struct SimplifyReport {
  size_t triangles_before = 0, triangles_after = 0;
  size_t vertices_welded = 0;  // duplicate positions merged before simplifying
  float error_m = 0;           // the largest deviation meshoptimizer reports (metres)
};

// Welds vertices at equal positions (attributes of the first kept), simplifies, and returns the
// mesh with the surviving vertices (each keeps its own colour, normal and class). A mesh already
// at or under the target is returned welded but otherwise unchanged.
TriangleMesh simplifyMesh(const TriangleMesh& mesh, const SimplifyOptions& options, SimplifyReport* report = nullptr);

}  // namespace vf
