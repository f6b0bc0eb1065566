#include "viewer/slice.h"

#include <tbb/parallel_for.h>

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <limits>

#include "core/error.h"

namespace vf::viewer {
namespace {

float component(const Vec3f& v, int axis) { return axis == 0 ? v.x : axis == 1 ? v.y : v.z; }
int component(const Vec3i& v, int axis) { return axis == 0 ? v.x : axis == 1 ? v.y : v.z; }
void setComponent(Vec3i& v, int axis, int value) { (axis == 0 ? v.x : axis == 1 ? v.y : v.z) = value; }

// Voxel size and the world position of voxel (0,0,0)'s centre: index <-> world without OpenVDB.
struct IndexFrame {
  Vec3f origin_m;
  float voxel_m;
  int toIndex(float world_m, int axis) const {
    return int(std::lround((world_m - component(origin_m, axis)) / voxel_m));
  }
  float toWorld(int index, int axis) const { return component(origin_m, axis) + float(index) * voxel_m; }
};

IndexFrame indexFrame(const Scene& scene) {
  return {sceneVoxelCenter(scene, {0, 0, 0}), scene.meta.voxel_size_m};
}

// The voxel index range of the observed voxels (bounds are the outer faces of those voxels).
void indexBounds(const Scene& scene, const SceneSummary& summary, Vec3i& lo, Vec3i& hi) {
  const IndexFrame f = indexFrame(scene);
  for (int a = 0; a < 3; ++a) {
    setComponent(lo, a, f.toIndex(component(summary.bounds_min_m, a) + 0.5f * f.voxel_m, a));
    setComponent(hi, a, f.toIndex(component(summary.bounds_max_m, a) - 0.5f * f.voxel_m, a));
  }
}

}  // namespace

SliceRange sliceRange(const Scene& scene, const SceneSummary& summary, int axis) {
  Vec3i lo{0, 0, 0}, hi{0, 0, 0};
  indexBounds(scene, summary, lo, hi);
  const IndexFrame f = indexFrame(scene);
  SliceRange r;
  r.first = component(lo, axis);
  r.last = component(hi, axis);
  r.first_m = f.toWorld(r.first, axis);
  r.last_m = f.toWorld(r.last, axis);
  return r;
}

int sliceIndexAt(const Scene& scene, const SceneSummary& summary, int axis, float value_m) {
  const SliceRange r = sliceRange(scene, summary, axis);
  const float half = 0.5f * indexFrame(scene).voxel_m;
  if (value_m < r.first_m - half || value_m > r.last_m + half) {
    char buf[256];
    std::snprintf(buf, sizeof buf, "--slice %s:%g lies outside the observed scene (%s from %.3f to %.3f m)",
                  axisName(axis), value_m, axisName(axis), r.first_m, r.last_m);
    throw Error(buf);
  }
  return std::clamp(indexFrame(scene).toIndex(value_m, axis), r.first, r.last);
}

SliceImage sampleSlice(const Scene& scene, const SceneSummary& summary, SliceGrid grid, int axis, int index) {
  Vec3i lo{0, 0, 0}, hi{0, 0, 0};
  indexBounds(scene, summary, lo, hi);
  const IndexFrame f = indexFrame(scene);
  const int u_axis = axis == 0 ? 1 : 0, v_axis = axis == 2 ? 1 : 2;
  SliceImage s;
  s.axis = axis;
  s.grid = grid;
  s.index = std::clamp(index, component(lo, axis), component(hi, axis));
  s.value_m = f.toWorld(s.index, axis);
  s.width = component(hi, u_axis) - component(lo, u_axis) + 1;
  s.height = component(hi, v_axis) - component(lo, v_axis) + 1;
  s.spacing_m = f.voxel_m;
  Vec3i first = lo;
  setComponent(first, axis, s.index);
  s.origin_m = {f.toWorld(first.x, 0), f.toWorld(first.y, 1), f.toWorld(first.z, 2)};
  s.values.assign(size_t(s.width) * size_t(s.height), std::numeric_limits<float>::quiet_NaN());
  // Tree reads are thread-safe; rows in parallel keep a 512^2 plane interactive.
  tbb::parallel_for(0, s.height, [&](int v) {
    Vec3i ijk = first;
    setComponent(ijk, v_axis, component(lo, v_axis) + v);
    for (int u = 0; u < s.width; ++u) {
      setComponent(ijk, u_axis, component(lo, u_axis) + u);
      const SceneVoxel voxel = sceneVoxel(scene, ijk);
      if (!voxel.active || voxel.weight <= 0) continue;  // unobserved: transparent
      s.values[size_t(v) * s.width + u] = grid == SliceGrid::kTsdf ? voxel.tsdf_m : voxel.weight;
    }
  });
  float max_weight = 0;
  for (float x : s.values)
    if (std::isfinite(x)) {
      ++s.observed;
      max_weight = std::max(max_weight, x);
    }
  if (grid == SliceGrid::kTsdf) {
    s.range_min = -scene.meta.truncation_m;
    s.range_max = scene.meta.truncation_m;
  } else {
    s.range_min = 0;
    s.range_max = max_weight > 0 ? max_weight : 1;
  }
  return s;
}

std::string sliceTitle(SliceGrid grid) { return grid == SliceGrid::kTsdf ? "tsdf [mm]" : "weight [frames]"; }
float sliceDisplayScale(SliceGrid grid) { return grid == SliceGrid::kTsdf ? 1000.f : 1.f; }

}  // namespace vf::viewer
