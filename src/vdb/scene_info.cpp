#include "vdb/scene_info.h"

#include <tbb/parallel_reduce.h>

#include <algorithm>
#include <cmath>
#include <map>

#include <openvdb/io/File.h>

#include <filesystem>

#include "core/error.h"
#include "core/similar_names.h"
#include "vdb/scene_grids.h"
#include "vdb/vdb_file_check.h"

namespace vf {
namespace {

GridSummary gridSummary(const openvdb::GridBase& grid) {
  return {grid.getName(), grid.valueType(), size_t(grid.activeVoxelCount()), size_t(grid.memUsage())};
}

// A grid's statistic as written by libopenvdb (GridBase::addStatsMetadata); null when missing.
template <class MetaT>
typename MetaT::ConstPtr gridStatistic(const openvdb::GridBase& grid, const char* key) {
  return grid.getMetadata<MetaT>(key);
}

template <class GridT>
void requireType(const openvdb::GridBase::Ptr& grid, const std::string& path) {
  if (grid && !grid->isType<GridT>())
    throw Error(path + ": grid '" + grid->getName() + "' has type " + grid->valueType() + ", expected " +
                openvdb::typeNameAsString<typename GridT::ValueType>());
}

}  // namespace

SceneHeader readSceneHeader(const std::string& path) {
  ensureOpenVdbInitialized();
  if (!std::filesystem::exists(path)) throw Error(noSuchPathMessage(path, "scene file"));
  const std::vector<std::string> names = {kTsdfGridName, kWeightGridName, kColorGridName, kClassGridName,
                                          kClassConfidenceGridName};
  // The headers libopenvdb reads below, checked as readScene checks the whole file.
  checkVdbFileHeaders(path, names);
  openvdb::MetaMap::Ptr file_meta;
  std::vector<openvdb::GridBase::Ptr> grids;
  try {
    openvdb::io::File file(path);
    file.open(/*delayLoad=*/false);
    file_meta = file.getMetadata();
    for (const std::string& name : names)
      grids.push_back(file.hasGrid(name) ? file.readGridMetadata(name) : nullptr);
    file.close();
  } catch (const std::exception& e) {
    throw Error(path + ": not a readable OpenVDB file (truncated or foreign?): " + e.what());
  }
  const openvdb::GridBase::Ptr& tsdf = grids[0];
  if (!tsdf) throw Error(path + ": not a vdbfuse scene: it has no '" + std::string(kTsdfGridName) + "' grid");
  if (!grids[1]) throw Error(path + ": not a vdbfuse scene: it has no '" + std::string(kWeightGridName) + "' grid");
  requireType<openvdb::FloatGrid>(grids[0], path);
  requireType<openvdb::FloatGrid>(grids[1], path);
  requireType<openvdb::Vec3SGrid>(grids[2], path);
  requireType<openvdb::Int32Grid>(grids[3], path);
  requireType<openvdb::FloatGrid>(grids[4], path);
  if (tsdf->getGridClass() != openvdb::GRID_LEVEL_SET) throw Error(path + ": grid 'tsdf' is not a level set");
  checkSceneGridTransforms(*tsdf, {grids[1].get(), grids[2].get(), grids[3].get(), grids[4].get()}, path);

  SceneHeader h;
  // The tsdf's background (its truncation) lives in its tree; vdbfuse states it in the metadata.
  h.meta = sceneMetadataFromFile(*file_meta, *tsdf, 0.f, path);
  h.has_classes = grids[3] != nullptr;
  SceneSummary& s = h.summary;
  for (const openvdb::GridBase::Ptr& grid : grids) {
    if (!grid) continue;
    const auto voxels = gridStatistic<openvdb::Int64Metadata>(*grid, openvdb::GridBase::META_FILE_VOXEL_COUNT);
    const auto bytes = gridStatistic<openvdb::Int64Metadata>(*grid, openvdb::GridBase::META_FILE_MEM_BYTES);
    if (!voxels || !bytes) return h;  // statistics_recorded stays false
    if (voxels->value() < 0 || bytes->value() < 0)
      throw Error(path + ": grid '" + grid->getName() + "' states negative statistics (a damaged or crafted file)");
    s.grids.push_back({grid->getName(), grid->valueType(), size_t(voxels->value()), size_t(bytes->value())});
    s.memory_bytes += size_t(bytes->value());
  }
  s.active_voxels = s.grids.front().active_voxels;
  s.empty = s.active_voxels == 0;
  if (!s.empty) {
    const auto lo = gridStatistic<openvdb::Vec3IMetadata>(*tsdf, openvdb::GridBase::META_FILE_BBOX_MIN);
    const auto hi = gridStatistic<openvdb::Vec3IMetadata>(*tsdf, openvdb::GridBase::META_FILE_BBOX_MAX);
    if (!lo || !hi) return h;
    // As summarizeScene: the outer faces of the extreme voxels.
    const openvdb::Vec3d a = tsdf->indexToWorld(openvdb::Vec3d(lo->value()) - openvdb::Vec3d(0.5));
    const openvdb::Vec3d b = tsdf->indexToWorld(openvdb::Vec3d(hi->value()) + openvdb::Vec3d(0.5));
    s.bounds_min_m = {float(a.x()), float(a.y()), float(a.z())};
    s.bounds_max_m = {float(b.x()), float(b.y()), float(b.z())};
  }
  h.statistics_recorded = true;
  return h;
}

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
