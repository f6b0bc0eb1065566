#include "vdb/scene_info.h"

#include <tbb/parallel_reduce.h>

#include <algorithm>
#include <cmath>
#include <map>

#include "vdb/scene_grids.h"

namespace vf {
namespace {

GridSummary gridSummary(const openvdb::GridBase& grid) {
  return {grid.getName(), grid.valueType(), size_t(grid.activeVoxelCount()), size_t(grid.memUsage())};
}

}  // namespace

SceneSummary summarizeScene(const Scene& scene, const Rigid3f& surface_frame) {
  const SceneGrids& g = scene.grids();
  SceneSummary s;
  for (const openvdb::GridBase* grid :
       {static_cast<const openvdb::GridBase*>(g.tsdf.get()), static_cast<const openvdb::GridBase*>(g.weight.get()),
        static_cast<const openvdb::GridBase*>(g.color.get()), static_cast<const openvdb::GridBase*>(g.class_id.get()),
        static_cast<const openvdb::GridBase*>(g.class_confidence.get())}) {
    if (!grid) continue;
    s.grids.push_back(gridSummary(*grid));
    s.memory_bytes += s.grids.back().memory_bytes;
  }
  if (!g.tsdf) return s;
  s.active_voxels = size_t(g.tsdf->activeVoxelCount());
  const openvdb::CoordBBox box = g.tsdf->evalActiveVoxelBoundingBox();
  s.empty = s.active_voxels == 0;
  if (!s.empty) {
    const openvdb::Vec3d lo = g.tsdf->indexToWorld(box.min().asVec3d() - openvdb::Vec3d(0.5));
    const openvdb::Vec3d hi = g.tsdf->indexToWorld(box.max().asVec3d() + openvdb::Vec3d(0.5));
    s.bounds_min_m = {float(lo.x()), float(lo.y()), float(lo.z())};
    s.bounds_max_m = {float(hi.x()), float(hi.y()), float(hi.z())};
  }
  const float voxel = float(g.tsdf->voxelSize()[0]);
  Vec3f lo{3e38f, 3e38f, 3e38f}, hi{-3e38f, -3e38f, -3e38f};
  for (auto it = g.tsdf->cbeginValueOn(); it; ++it) {
    if (!(std::fabs(*it) < voxel)) continue;
    ++s.surface_voxels;
    const openvdb::Vec3d w = g.tsdf->indexToWorld(it.getCoord());
    const Vec3f p = surface_frame * Vec3f{float(w.x()), float(w.y()), float(w.z())};
    lo = {std::min(lo.x, p.x), std::min(lo.y, p.y), std::min(lo.z, p.z)};
    hi = {std::max(hi.x, p.x), std::max(hi.y, p.y), std::max(hi.z, p.z)};
  }
  if (s.surface_voxels > 0) s.surface_min_m = lo, s.surface_max_m = hi;
  if (g.class_id) {
    std::map<int, size_t> counts;
    for (auto it = g.class_id->cbeginValueOn(); it; ++it) counts[*it] += it.getVoxelCount();
    for (const auto& [id, n] : counts) {
      const ClassInfo* c = scene.meta.classes.findId(id);
      s.classes.push_back({id, c ? c->name : (id < 0 ? "unknown" : "(not in table)"), n});
    }
  }
  return s;
}

SceneVoxel sceneVoxel(const Scene& scene, Vec3i ijk) {
  const SceneGrids& g = scene.grids();
  const openvdb::Coord c(ijk.x, ijk.y, ijk.z);
  SceneVoxel v;
  v.active = g.tsdf->tree().isValueOn(c);
  v.tsdf_m = g.tsdf->tree().getValue(c);
  v.weight = g.weight ? g.weight->tree().getValue(c) : 0.f;
  if (g.color) {
    const openvdb::Vec3s col = g.color->tree().getValue(c);
    v.color_linear = {col.x(), col.y(), col.z()};
  }
  if (g.class_id) v.class_id = g.class_id->tree().getValue(c);
  if (g.class_confidence) v.class_confidence = g.class_confidence->tree().getValue(c);
  return v;
}

Vec3f sceneVoxelCenter(const Scene& scene, Vec3i ijk) {
  const openvdb::Vec3d p = scene.grids().tsdf->indexToWorld(openvdb::Vec3d(ijk.x, ijk.y, ijk.z));
  return {float(p.x()), float(p.y()), float(p.z())};
}

}  // namespace vf
