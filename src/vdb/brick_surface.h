#pragma once
// Surface samples straight from the fused bricks, without building the scene's grids.
#include "core/brick_volume.h"
#include "core/mesh.h"

namespace vf {

// Positions and normals of the surface samples of `bricks` (vdb/surface_point.h): the points
// scenePointCloud gives for sceneFromBricks(bricks), bricks taken in the order of their
// coordinates (z, y, x) whatever their pool slots, so a fit over them is the same on every run
// of the same input. `keep_one_in` > 1 keeps
// about one sample in that many, picked by a hash of the voxel's coordinates, so the samples
// stay spread evenly over the surface (equal-area) and are the same on every run.
TriangleMesh brickSurfaceSamples(const BrickVolumeView& bricks, int keep_one_in = 1);

}  // namespace vf
