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
  // The surface voxels' centres in summarizeScene's surface_frame (no surface: lo > hi).
  Vec3f surface_min_m{1, 1, 1}, surface_max_m{0, 0, 0};
  size_t memory_bytes = 0;        // all grids
  std::vector<ClassVoxelCount> classes;  // active class-grid voxels per class, by id
};

// `surface_frame`: the frame in which the surface bounds are taken (info passes the Z-up export
// rotation, so that they are the coordinates Blender shows and --crop-axes z-up takes).
SceneSummary summarizeScene(const Scene& scene, const Rigid3f& surface_frame = Rigid3f::identity());

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
