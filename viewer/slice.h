#pragma once
// A plane of voxel samples from the TSDF or weight grid, as a plain image for the viewer's slice
// actor and color bar: across a world axis, or level (a floor plan at a height above the floor,
// in the scene's level frame).
#include <string>
#include <vector>

#include "core/math.h"
#include "vdb/scene.h"
#include "vdb/scene_info.h"
#include "viewer/level_frame.h"
#include "viewer/view_options.h"

namespace vf::viewer {

struct SliceImage {
  bool level = false;    // a floor plan (sampleLevelSlice), else across `axis`
  int axis = 2;          // normal axis: 0 x, 1 y, 2 z
  int index = 0;         // voxel index along the axis
  float value_m = 0;     // world coordinate of the plane (voxel centres); level: metres above the floor
  SliceGrid grid = SliceGrid::kTsdf;
  // An axis slice spans the two other axes in increasing order (z-slice: u = x, v = y;
  // y-slice: u = x, v = z; x-slice: u = y, v = z), one sample per voxel centre. A level slice
  // spans the level frame's right (u) and forward (v), one sample per voxel size, each the
  // nearest voxel's value.
  int width = 0, height = 0;
  Vec3f u_dir{1, 0, 0}, v_dir{0, 1, 0}, normal{0, 0, 1};  // world, unit: normal = u_dir x v_dir
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

// The heights above the floor (frame.floor_m) that the observed voxels' box spans along up.
struct LevelRange {
  float lowest_m = 0, highest_m = 0;
};
LevelRange levelSliceRange(const SceneSummary& summary, const LevelFrame& frame);
// Throws vf::Error when `height_m` above the floor lies outside levelSliceRange (the message
// gives the range).
void requireLevelInRange(const SceneSummary& summary, const LevelFrame& frame, float height_m);

// The horizontal plane `height_m` above the floor, over the observed voxels' extent. Color bar
// range as sampleSlice's.
SliceImage sampleLevelSlice(const Scene& scene, const SceneSummary& summary, const LevelFrame& frame, SliceGrid grid,
                            float height_m);

// Samples plane `index` (clamped to the range). Color bar range: tsdf -truncation..+truncation
// (metres), weight 0..the largest weight in the slice.
SliceImage sampleSlice(const Scene& scene, const SceneSummary& summary, SliceGrid grid, int axis, int index);

// The color bar shows tsdf in millimetres (a truncation of 0.0293 m reads as 29): its title
// "tsdf [mm]" and the factor from the slice's values; weight as it is (frames that observed
// the voxel), "weight [frames]": short enough for the color bar at 640 px.
std::string sliceTitle(SliceGrid grid);
float sliceDisplayScale(SliceGrid grid);

}  // namespace vf::viewer
