#pragma once
// An axis-aligned plane of voxel samples from the TSDF or weight grid, as a plain image for the
// viewer's slice actor and color bar.
#include <string>
#include <vector>

#include "core/math.h"
#include "vdb/scene.h"
#include "vdb/scene_info.h"
#include "viewer/view_options.h"

namespace vf::viewer {

struct SliceImage {
  int axis = 2;          // normal axis: 0 x, 1 y, 2 z
  int index = 0;         // voxel index along the axis
  float value_m = 0;     // world coordinate of the plane (voxel centres)
  SliceGrid grid = SliceGrid::kTsdf;
  // The image spans the two other axes in increasing order (z-slice: u = x, v = y;
  // y-slice: u = x, v = z; x-slice: u = y, v = z), one sample per voxel centre.
  int width = 0, height = 0;
  Vec3f origin_m{0, 0, 0};  // world position of sample (0, 0)
  float spacing_m = 0;
  std::vector<float> values;  // width * height, u fastest; NaN where the voxel was not observed
  float range_min = 0, range_max = 0;  // the color bar's range
  size_t observed = 0;                  // finite samples
};

// Voxel-index extent of the scene's observed voxels along `axis` (inclusive).
struct SliceRange {
  int first = 0, last = 0;
  float first_m = 0, last_m = 0;  // world coordinates of those voxel centres
};
SliceRange sliceRange(const Scene& scene, const SceneSummary& summary, int axis);

// Voxel index of the plane nearest to `value_m` along `axis`. Throws vf::Error when the value
// lies outside the observed voxels (the message gives the valid range).
int sliceIndexAt(const Scene& scene, const SceneSummary& summary, int axis, float value_m);

// Samples plane `index` (clamped to the range). Color bar range: tsdf -truncation..+truncation
// (metres), weight 0..the largest weight in the slice.
SliceImage sampleSlice(const Scene& scene, const SceneSummary& summary, SliceGrid grid, int axis, int index);

// The color bar shows tsdf in millimetres (a truncation of 0.0293 m reads as 29): its title
// "tsdf [mm]" and the factor from the slice's values; weight as it is (frames that observed
// the voxel), "weight [frames]": short enough for the color bar at 640 px.
std::string sliceTitle(SliceGrid grid);
float sliceDisplayScale(SliceGrid grid);

}  // namespace vf::viewer
