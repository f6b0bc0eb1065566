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

// What the file's headers say about a scene, without reading a voxel tree: the file's metadata
// and, per grid, the statistics libopenvdb writes beside every grid (file_voxel_count,
// file_bbox_min/max, file_mem_bytes). Milliseconds and a few MB for a scene of any size, where
// readScene + summarizeScene of a 270 MB room took 2.8 s and 1.3 GB. summary.surface_voxels,
// the surface bounds and the class counts are left unset: they need the trees (summarizeScene).
// Throws vf::Error as readScene does for a missing, damaged or foreign file (its header
// structure, grid types and transforms are checked).
struct SceneHeader {
  SceneMetadata meta;
  SceneSummary summary;      // valid when statistics_recorded
  bool has_classes = false;  // a class grid is present
  // False for a file whose grids lack the statistics (written by a tool that turned them off):
  // its voxels must be read to count them.
  bool statistics_recorded = false;
};
SceneHeader readSceneHeader(const std::string& path);

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
