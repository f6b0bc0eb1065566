#pragma once
// What `vdbfuse info` reports, and single-voxel reads for tests and tools.
#include <cstddef>
#include <string>
#include <vector>

#include "core/math.h"
#include "vdb/scene.h"

namespace vf {

struct GridSummary {
  std::string name, value_type;
  size_t active_voxels = 0;
  size_t memory_bytes = 0;
};

struct ClassVoxelCount {
  int id = 0;
  std::string name;  // from the class table; "unknown" for -1, "(not in table)" otherwise
  size_t voxels = 0;
};

struct SceneSummary {
  std::vector<GridSummary> grids;
  size_t active_voxels = 0;       // tsdf
  size_t surface_voxels = 0;      // tsdf voxels with |sdf| < one voxel
  bool empty = true;
  Vec3f bounds_min_m{0, 0, 0}, bounds_max_m{0, 0, 0};  // outer faces of the active voxels
  size_t memory_bytes = 0;        // all grids
  std::vector<ClassVoxelCount> classes;  // active class-grid voxels per class, by id
};

SceneSummary summarizeScene(const Scene& scene);

// One voxel of every grid, by index coordinate (the dense volume's voxel index).
struct SceneVoxel {
  bool active = false;
  float tsdf_m = 0, weight = 0;
  Vec3f color_linear{0, 0, 0};
  int class_id = kSceneUnknownClass;
  float class_confidence = 0;
};
SceneVoxel sceneVoxel(const Scene& scene, Vec3i ijk);

// World position of voxel ijk's sample (cell centre).
Vec3f sceneVoxelCenter(const Scene& scene, Vec3i ijk);

}  // namespace vf
