#include "viewer/slice.h"

#include <tbb/parallel_for.h>

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <limits>
#include <vector>

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

// The corners of the observed voxels' box.
std::vector<Vec3f> boundsCorners(const SceneSummary& summary) {
  std::vector<Vec3f> corners;
  const Vec3f lo = summary.bounds_min_m, hi = summary.bounds_max_m;
  for (int c = 0; c < 8; ++c) corners.push_back({c & 1 ? hi.x : lo.x, c & 2 ? hi.y : lo.y, c & 4 ? hi.z : lo.z});
  return corners;
}

// The color bar's range (tsdf: -truncation..+truncation; weight: 0..the largest weight) and
// the count of observed samples.
void finishSlice(SliceImage& s, const Scene& scene) {
  float max_weight = 0;
  for (float x : s.values)
    if (std::isfinite(x)) {
      ++s.observed;
      max_weight = std::max(max_weight, x);
    }
  if (s.grid == SliceGrid::kTsdf) {
    s.range_min = -scene.meta.truncation_m;
    s.range_max = scene.meta.truncation_m;
  } else {
    s.range_min = 0;
    s.range_max = max_weight > 0 ? max_weight : 1;
  }
}

}  // namespace

LevelRange levelSliceRange(const SceneSummary& summary, const LevelFrame& frame) {
  LevelRange r{std::numeric_limits<float>::infinity(), -std::numeric_limits<float>::infinity()};
  for (const Vec3f& c : boundsCorners(summary)) {
    const float h = dot(c, frame.up) - float(frame.floor_m);
    r.lowest_m = std::min(r.lowest_m, h);
    r.highest_m = std::max(r.highest_m, h);
  }
  return r;
}

void requireLevelInRange(const SceneSummary& summary, const LevelFrame& frame, float height_m) {
  const LevelRange r = levelSliceRange(summary, frame);
  if (height_m >= r.lowest_m && height_m <= r.highest_m) return;
  char buf[256];
  std::snprintf(buf, sizeof buf, "--slice height=%g lies outside the observed scene (heights %.2f to %.2f m above "
                "the floor)", height_m, r.lowest_m, r.highest_m);
  throw Error(buf);
}

SliceImage sampleLevelSlice(const Scene& scene, const SceneSummary& summary, const LevelFrame& frame, SliceGrid grid,
                            float height_m) {
  const IndexFrame f = indexFrame(scene);
  const float inf = std::numeric_limits<float>::infinity();
  float u0 = inf, u1 = -inf, v0 = inf, v1 = -inf;
  for (const Vec3f& c : boundsCorners(summary)) {
    u0 = std::min(u0, dot(c, frame.right)), u1 = std::max(u1, dot(c, frame.right));
    v0 = std::min(v0, dot(c, frame.forward)), v1 = std::max(v1, dot(c, frame.forward));
  }
  SliceImage s;
  s.level = true;
  s.grid = grid;
  s.value_m = height_m;
  s.index = int(std::lround(height_m / f.voxel_m));
  s.spacing_m = f.voxel_m;
  s.u_dir = frame.right;
  s.v_dir = frame.forward;
  s.normal = frame.up;
  s.width = std::max(1, int(std::ceil((u1 - u0) / f.voxel_m)) + 1);
  s.height = std::max(1, int(std::ceil((v1 - v0) / f.voxel_m)) + 1);
  s.origin_m = frame.toWorld({u0, v0, float(frame.floor_m) + height_m});
  s.values.assign(size_t(s.width) * size_t(s.height), std::numeric_limits<float>::quiet_NaN());
  tbb::parallel_for(0, s.height, [&](int v) {
    for (int u = 0; u < s.width; ++u) {
      const Vec3f p = s.origin_m + s.u_dir * (float(u) * f.voxel_m) + s.v_dir * (float(v) * f.voxel_m);
      const Vec3i ijk{f.toIndex(p.x, 0), f.toIndex(p.y, 1), f.toIndex(p.z, 2)};
      const SceneVoxel voxel = sceneVoxel(scene, ijk);
      if (!voxel.active || voxel.weight <= 0) continue;  // unobserved: transparent
      s.values[size_t(v) * s.width + u] = grid == SliceGrid::kTsdf ? voxel.tsdf_m : voxel.weight;
    }
  });
  finishSlice(s, scene);
  return s;
}

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
  const Vec3f unit[3] = {{1, 0, 0}, {0, 1, 0}, {0, 0, 1}};
  s.u_dir = unit[u_axis];
  s.v_dir = unit[v_axis];
  s.normal = cross(s.u_dir, s.v_dir);  // +-the axis: a rotation places the image (slice_actor.cpp)
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
  finishSlice(s, scene);
  return s;
}

std::string sliceTitle(SliceGrid grid) { return grid == SliceGrid::kTsdf ? "tsdf [mm]" : "weight [frames]"; }
float sliceDisplayScale(SliceGrid grid) { return grid == SliceGrid::kTsdf ? 1000.f : 1.f; }

}  // namespace vf::viewer
