#pragma once
// Exports that need the grids themselves: the Blender volume and the surface point cloud.
#include <string>
#include <vector>

#include "core/mesh.h"
#include "vdb/mesher.h"
#include "vdb/scene.h"

namespace vf {

// A .vdb for Blender's Volume object: a fog `density` grid (openvdb::tools::sdfToFogVolume of
// the tsdf: 0 outside, rising to 1 at the truncation depth behind the surface; only the observed
// band is filled) and the linear `color` grid, the names Principled Volume's Density and Color
// attributes read. Atomic like every writer. `to_file` rotates the grids' transform into the
// export frame (vdb/scene_frame.h), so that the volume lines up with the meshes written beside it.
struct BlenderVolumeInfo {
  float density_min = 0, density_max = 0;  // over the active voxels
  float band_m = 0;                         // depth of the fog band behind the surface (the truncation)
};
BlenderVolumeInfo writeBlenderVolume(const Scene& scene, const std::string& path,
                                     const Rigid3f& to_file = Rigid3f::identity());

// One point per zero-crossing voxel (a voxel whose face neighbour is observed and of the other
// sign, taking the one nearer the surface), moved onto the surface along the TSDF gradient,
// with normal, color (sRGB 8 bit or class color) and class. No triangles.
TriangleMesh scenePointCloud(const Scene& scene, const MeshOptions& options = {});

// Names of the grids in any .vdb file (throws vf::Error naming the file when unreadable).
std::vector<std::string> vdbGridNames(const std::string& path);

}  // namespace vf
