#include "vdb/scene_edit.h"

#include <openvdb/tools/LevelSetFilter.h>
#include <tbb/parallel_for.h>

#include <atomic>
#include <cmath>
#include <numeric>

#include "core/error.h"
#include "vdb/scene_grids.h"

namespace vf {
namespace {

using FloatLeaf = openvdb::FloatTree::LeafNodeType;

// A mask of the tsdf voxels for which pred(ijk, leaf, offset) holds.
template <class Pred>
openvdb::MaskGrid::Ptr maskWhere(const SceneGrids& g, Pred pred) {
  auto mask = openvdb::MaskGrid::create();
  std::vector<const FloatLeaf*> leaves;
  g.tsdf->tree().getNodes(leaves);
  std::vector<openvdb::MaskTree::LeafNodeType*> out(leaves.size(), nullptr);
  tbb::parallel_for(tbb::blocked_range<size_t>(0, leaves.size()), [&](const auto& r) {
    for (size_t n = r.begin(); n != r.end(); ++n) {
      openvdb::MaskTree::LeafNodeType* m = nullptr;
      for (auto it = leaves[n]->cbeginValueOn(); it; ++it) {
        if (!pred(it.getCoord(), *leaves[n], it.pos())) continue;
        if (!m) m = new openvdb::MaskTree::LeafNodeType(leaves[n]->origin(), false);
        m->setValueOn(it.pos());
      }
      out[n] = m;
    }
  });
  for (auto* m : out)
    if (m) mask->tree().addLeaf(m);
  return mask;
}

}  // namespace

size_t excludeClassVoxels(Scene& scene, const std::set<int>& ids) {
  SceneGrids& g = scene.grids();
  if (!g.class_id) throw Error("excludeClassVoxels: the scene has no class grid (fused without labels)");
  const openvdb::Int32Tree& classes = g.class_id->tree();
  auto mask = maskWhere(g, [&](const openvdb::Coord& ijk, const FloatLeaf&, openvdb::Index) {
    return ids.count(classes.getValue(ijk)) > 0;
  });
  return removeMaskedVoxels(g, *mask);
}

size_t cropToBox(Scene& scene, Vec3f min_m, Vec3f max_m) {
  if (!(min_m.x < max_m.x && min_m.y < max_m.y && min_m.z < max_m.z))
    throw Error("cropToBox: need xmin < xmax, ymin < ymax and zmin < zmax");
  SceneGrids& g = scene.grids();
  const openvdb::math::Transform& xform = g.tsdf->transform();
  auto mask = maskWhere(g, [&](const openvdb::Coord& ijk, const FloatLeaf&, openvdb::Index) {
    const openvdb::Vec3d p = xform.indexToWorld(ijk);
    return p.x() < min_m.x || p.y() < min_m.y || p.z() < min_m.z || p.x() > max_m.x || p.y() > max_m.y ||
           p.z() > max_m.z;
  });
  return removeMaskedVoxels(g, *mask);
}

OutlierReport removeOutliers(Scene& scene, const OutlierOptions& options) {
  SceneGrids& g = scene.grids();
  OutlierReport report;
  if (options.min_weight > 0) {
    const openvdb::FloatTree& weight = g.weight->tree();
    auto mask = maskWhere(g, [&](const openvdb::Coord& ijk, const FloatLeaf&, openvdb::Index) {
      return weight.getValue(ijk) < options.min_weight;
    });
    report.weak_voxels = removeMaskedVoxels(g, *mask);
  }
  if (options.min_component_voxels <= 1) return report;

  // Face-connected components of the active band: number the voxels through an Int32 tree of
  // the same topology, then union-find.
  openvdb::Int32Tree ids(g.tsdf->tree(), -1, openvdb::TopologyCopy());
  std::vector<openvdb::Int32Tree::LeafNodeType*> leaves;
  ids.getNodes(leaves);
  std::vector<int32_t> base(leaves.size() + 1, 0);
  for (size_t n = 0; n < leaves.size(); ++n) base[n + 1] = base[n] + int32_t(leaves[n]->onVoxelCount());
  tbb::parallel_for(tbb::blocked_range<size_t>(0, leaves.size()), [&](const auto& r) {
    for (size_t n = r.begin(); n != r.end(); ++n) {
      int32_t next = base[n];
      for (auto it = leaves[n]->beginValueOn(); it; ++it) it.setValue(next++);
    }
  });
  std::vector<int32_t> parent(size_t(base.back()));
  std::iota(parent.begin(), parent.end(), 0);
  auto find = [&](int32_t v) {
    while (parent[v] != v) v = parent[v] = parent[parent[v]];
    return v;
  };
  openvdb::tree::ValueAccessor<const openvdb::Int32Tree> acc(ids);
  for (auto* leaf : leaves)
    for (auto it = leaf->cbeginValueOn(); it; ++it)
      for (int a = 0; a < 3; ++a) {
        openvdb::Coord nb = it.getCoord();
        nb[a] += 1;
        int32_t other;
        if (!acc.probeValue(nb, other)) continue;
        const int32_t x = find(*it), y = find(other);
        if (x != y) parent[std::max(x, y)] = std::min(x, y);
      }
  std::vector<int32_t> size(parent.size(), 0);
  for (int32_t v = 0; v < int32_t(parent.size()); ++v) ++size[find(v)];
  for (int32_t v = 0; v < int32_t(parent.size()); ++v) {
    if (parent[v] != v) continue;
    if (size_t(size[v]) < options.min_component_voxels) {
      ++report.components_removed;
      report.component_voxels += size_t(size[v]);
    } else {
      ++report.components_kept;
    }
  }
  if (report.components_removed == 0) return report;
  auto mask = maskWhere(g, [&](const openvdb::Coord& ijk, const FloatLeaf&, openvdb::Index) {
    return size_t(size[find(ids.getValue(ijk))]) < options.min_component_voxels;
  });
  removeMaskedVoxels(g, *mask);
  return report;
}

size_t smoothScene(Scene& scene, int iterations) {
  if (iterations <= 0) return 0;
  SceneGrids& g = scene.grids();
  const float trunc = g.tsdf->background();
  openvdb::FloatGrid::Ptr filtered = g.tsdf->deepCopy();
  {
    openvdb::tools::LevelSetFilter<openvdb::FloatGrid> filter(*filtered);
    for (int i = 0; i < iterations; ++i) filter.meanCurvature();
  }
  std::vector<FloatLeaf*> leaves;
  g.tsdf->tree().getNodes(leaves);
  std::atomic<size_t> changed{0};
  tbb::parallel_for(tbb::blocked_range<size_t>(0, leaves.size()), [&](const auto& r) {
    openvdb::tree::ValueAccessor<const openvdb::FloatTree> acc(filtered->tree());
    size_t local = 0;
    for (size_t n = r.begin(); n != r.end(); ++n)
      for (auto it = leaves[n]->beginValueOn(); it; ++it) {
        if (std::fabs(*it) >= 0.5f * trunc) continue;
        float v;
        if (!acc.probeValue(it.getCoord(), v)) continue;
        v = std::clamp(v, -trunc, trunc);
        if (v != *it) {
          it.setValue(v);
          ++local;
        }
      }
    changed += local;
  });
  return changed;
}

}  // namespace vf
