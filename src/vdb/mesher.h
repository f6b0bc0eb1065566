#pragma once
// Marching cubes on the scene's TSDF: the surface where it was observed, with colors and classes.
#include "core/mesh.h"
#include "vdb/scene.h"
#include "vdb/vertex_color.h"

namespace vf {

struct MeshOptions {
  // Voxels observed fewer times than this are treated as unobserved (no surface through them).
  float min_weight = 0.f;
  MeshColorMode color = MeshColorMode::kRgb;
};

// One vertex per sign change of the TSDF along a voxel edge whose two voxels are both observed;
// a cube is triangulated only when all eight of its voxels are observed, so nothing is invented
// across unobserved space. Vertices shared between cubes are shared in the mesh (watertight
// where observed). Colors (vdb/vertex_color.h): interpolated along the edge from `color`, or the
// class table's color; classes: the nearer voxel's class (when the scene has classes).
TriangleMesh meshScene(const Scene& scene, const MeshOptions& options = {});

}  // namespace vf
