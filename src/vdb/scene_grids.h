#pragma once
// The OpenVDB side of a Scene. Only src/vdb/*.cpp include this (OpenVDB templates compile slowly).
#include "vdb/openvdb_extern_grids.h"

#include <string>
#include <vector>

#include "core/math.h"
#include "vdb/openvdb_init.h"
#include "vdb/scene.h"

namespace vf {

// All grids share one transform and the tsdf's active topology (class/confidence grids exist
// only when the scene was fused with labels).
struct SceneGrids {
  openvdb::FloatGrid::Ptr tsdf;              // level set, metres, background +truncation
  openvdb::FloatGrid::Ptr weight;            // observation count, background 0
  openvdb::Vec3SGrid::Ptr color;             // linear RGB 0..1, background 0
  openvdb::Int32Grid::Ptr class_id;          // class id, background kSceneUnknownClass
  openvdb::FloatGrid::Ptr class_confidence;  // vote confidence, background 0
};

// Deactivates the voxels active in `mask` in every grid (values back to each grid's background)
// and prunes emptied leaves, so that all grids keep the tsdf's topology. Returns how many tsdf
// voxels were active before and are not any more.
size_t removeMaskedVoxels(SceneGrids& grids, const openvdb::MaskGrid& mask);

// How a scene grid is stored in the file, for every scene writer (writeScene,
// writeSceneFromBricks): float and vector grids as half floats (readers get floats back), a
// third of the file; the TSDF keeps 2^-11 of its value, colour bytes and counts up to 2048 come
// back exactly. Integer grids (class ids) as they are.
inline void setSceneGridStorage(openvdb::GridBase& grid) {
  grid.setSaveFloatAsHalf(grid.isType<openvdb::FloatGrid>() || grid.isType<openvdb::Vec3SGrid>());
}

// Writes a .vdb through a temp file beside `path`, renamed into place; on error no file is left
// and vf::Error says "PATH: cannot write WHAT: why".
void writeVdbFileAtomic(const std::string& path, const openvdb::GridPtrVec& grids, const openvdb::MetaMap& meta,
                        const std::string& what);

// The file-level metadata of a scene (voxel size, classes, source, up, camera...).
openvdb::MetaMap sceneFileMetadata(const SceneMetadata& meta);

// Every grid in one uniform, axis-scaled frame with a sane voxel (10 um .. 10 m): anything else
// (a crafted transform, zero or non-finite scale) meshes to NaN or infinite coordinates. Throws
// vf::Error naming `path` and the grid. Null entries of `others` are skipped.
void checkSceneGridTransforms(const openvdb::GridBase& tsdf, const std::vector<const openvdb::GridBase*>& others,
                              const std::string& path);

// The scene's metadata from the file's metadata and the tsdf grid's transform (the voxel size,
// which the metadata must agree with); the truncation is `fallback_truncation_m` (the tsdf's
// background) where the file does not state it. Throws vf::Error naming `path` for a table or
// vector that is not what vdbfuse writes.
SceneMetadata sceneMetadataFromFile(const openvdb::MetaMap& file_meta, const openvdb::GridBase& tsdf,
                                    float fallback_truncation_m, const std::string& path);

// The scene's voxel-to-world transform: index (i,j,k) sits at (i+0.5, j+0.5, k+0.5) * voxel in the
// fusion world frame (cell centred, as core/brick_volume.h).
openvdb::math::Transform::Ptr sceneTransform(float voxel_size_m);

}  // namespace vf
