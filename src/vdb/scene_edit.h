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

// Keeps only voxels whose centre lies inside [min_m, max_m]; returns tsdf voxels removed.
size_t cropToBox(Scene& scene, Vec3f min_m, Vec3f max_m);

struct OutlierOptions {
  float min_weight = 0.f;             // voxels observed fewer times are dropped (0 = keep all)
  size_t min_component_voxels = 0;    // face-connected pieces of the band smaller than this go
};
struct OutlierReport {
  size_t weak_voxels = 0;
  size_t components_removed = 0;
  size_t component_voxels = 0;
  size_t components_kept = 0;
};
OutlierReport removeOutliers(Scene& scene, const OutlierOptions& options);

// `iterations` passes of openvdb::tools::LevelSetFilter mean-curvature flow on the tsdf. The
// active set is kept as it was; voxels farther than half the truncation from the surface keep
// their values (the filter's renormalisation would otherwise bend the band's far edge, where
// observed negative values meet unobserved background, into new zero crossings).
// Returns the number of voxels whose value changed.
size_t smoothScene(Scene& scene, int iterations);

}  // namespace vf
