#pragma once
// Offline edits of the scene document. Each works in place on the Scene it is given (callers
// clone or read a fresh copy; files are never modified in place) and reports what it removed.
#include <cstddef>
#include <set>

#include "core/math.h"
#include "vdb/scene.h"

namespace vf {

// Deactivates every voxel whose class is in `ids` in all grids; returns tsdf voxels removed.
size_t excludeClassVoxels(Scene& scene, const std::set<int>& ids);

// Keeps only voxels whose centre lies inside [min_m, max_m]; returns tsdf voxels removed. The box
// is axis-aligned in the frame that `box_from_scene` takes scene positions into: the scene's own
// by default, or an export frame (exportRotation: the Z-up of a PLY in Blender), so that a box
// read off an exported mesh crops what it showed.
size_t cropToBox(Scene& scene, Vec3f min_m, Vec3f max_m, const Rigid3f& box_from_scene = Rigid3f::identity());

// Outlier removal, in two named parts:
// - weakly observed voxels: weight below `min_weight` (0 keeps all);
// - small pieces: connected pieces of the surface (as `mesh` cuts it, faces sharing a vertex)
//   with fewer than `min_component_triangles` faces. Their voxels are deactivated, the scene
//   is meshed again, and so on until no piece is under the threshold (cutting a piece's voxels
//   can split a neighbour), at most `max_passes` times. So `mesh --min-component N` on the result
//   finds nothing to remove (at --min-weight 0). Then the parts of the band (face-connected
//   voxels) that no surface passes through any more go too: fog without a surface.
struct OutlierOptions {
  float min_weight = 0.f;
  size_t min_component_triangles = 0;
  int max_passes = 8;
};
struct OutlierReport {
  size_t weak_voxels = 0;
  size_t pieces_before = 0, small_pieces_before = 0;  // the surface before the piece filter
  size_t piece_voxels = 0;                            // voxels removed with the small pieces
  size_t pieces_after = 0, small_pieces_after = 0;    // small_pieces_after is 0 unless max_passes ran out
  size_t bare_band_voxels = 0;                        // band left without a surface, removed
  int passes = 0;
};
OutlierReport removeOutliers(Scene& scene, const OutlierOptions& options);

// `iterations` passes of openvdb::tools::LevelSetFilter mean-curvature flow on the tsdf. The
// active set is kept as it was; voxels farther than half the truncation from the surface keep
// their values (the filter's renormalisation would otherwise bend the band's far edge, where
// observed negative values meet unobserved background, into new zero crossings).
// Returns the number of voxels whose value changed.
size_t smoothScene(Scene& scene, int iterations);

}  // namespace vf
