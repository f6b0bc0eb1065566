#include "vdb/scene_edit.h"

#include <openvdb/tools/LevelSetFilter.h>
#include <tbb/parallel_for.h>

#include <atomic>
#include <cstdint>
#include <cmath>
#include <memory>

#include "core/error.h"
#include "core/union_find.h"
#include "vdb/mesh_ops.h"
#include "vdb/mesher.h"
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

// The voxels at both ends of the edge each vertex with marked[v] == want lies on (a vertex
// exactly on a voxel: that voxel), from its position in index space: the voxels the surface
// passes between.
openvdb::MaskGrid::Ptr edgeVoxels(const SceneGrids& g, const TriangleMesh& mesh, const std::vector<bool>& marked,
                                  bool want) {
  auto mask = openvdb::MaskGrid::create();
  openvdb::tree::ValueAccessor<openvdb::MaskTree> acc(mask->tree());
  const openvdb::math::Transform& xform = g.tsdf->transform();
  for (size_t v = 0; v < mesh.positions.size(); ++v) {
    if (marked[v] != want) continue;
    const Vec3f& p = mesh.positions[v];
    const openvdb::Vec3d x = xform.worldToIndex(openvdb::Vec3d(p.x, p.y, p.z));
    int lo[3], hi[3];
    for (int a = 0; a < 3; ++a) {
      const double r = std::round(x[a]);
      const bool on_voxel = std::fabs(x[a] - r) < 1e-3;
      lo[a] = on_voxel ? int(r) : int(std::floor(x[a]));
      hi[a] = on_voxel ? int(r) : lo[a] + 1;
    }
    for (int i = lo[0]; i <= hi[0]; ++i)
      for (int j = lo[1]; j <= hi[1]; ++j)
        for (int k = lo[2]; k <= hi[2]; ++k) acc.setValueOn(openvdb::Coord(i, j, k));
  }
  return mask;
}

// Face-connected parts of the active band: every voxel numbered through an Int32 tree of the
// tsdf's topology, then union-find over the numbers; parent[number] ends as the part's root.
struct VoxelComponents {
  std::unique_ptr<openvdb::Int32Tree> ids;
  std::vector<openvdb::Int32Tree::LeafNodeType*> leaves;
  std::vector<int32_t> parent;
};

VoxelComponents voxelComponents(const SceneGrids& g) {
  VoxelComponents c;
  c.ids = std::make_unique<openvdb::Int32Tree>(g.tsdf->tree(), -1, openvdb::TopologyCopy());
  c.ids->getNodes(c.leaves);
  std::vector<int32_t> base(c.leaves.size() + 1, 0);
  for (size_t n = 0; n < c.leaves.size(); ++n) base[n + 1] = base[n] + int32_t(c.leaves[n]->onVoxelCount());
  tbb::parallel_for(tbb::blocked_range<size_t>(0, c.leaves.size()), [&](const auto& r) {
    for (size_t n = r.begin(); n != r.end(); ++n) {
      int32_t next = base[n];
      for (auto it = c.leaves[n]->beginValueOn(); it; ++it) it.setValue(next++);
    }
  });
  UnionFind parts(size_t(base.back()));
  openvdb::tree::ValueAccessor<const openvdb::Int32Tree> acc(*c.ids);
  for (const auto* leaf : c.leaves)
    for (auto it = leaf->cbeginValueOn(); it; ++it)
      for (int a = 0; a < 3; ++a) {
        openvdb::Coord nb = it.getCoord();
        nb[a] += 1;
        int32_t other;
        if (!acc.probeValue(nb, other)) continue;
        parts.unite(*it, other);
      }
  c.parent = parts.flatten();
  return c;
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

size_t cropToBox(Scene& scene, Vec3f min_m, Vec3f max_m, const Rigid3f& box_from_scene) {
  if (!(min_m.x < max_m.x && min_m.y < max_m.y && min_m.z < max_m.z))
    throw Error("crop box: need xmin < xmax, ymin < ymax and zmin < zmax");
  SceneGrids& g = scene.grids();
  const openvdb::math::Transform& xform = g.tsdf->transform();
  auto mask = maskWhere(g, [&](const openvdb::Coord& ijk, const FloatLeaf&, openvdb::Index) {
    const openvdb::Vec3d w = xform.indexToWorld(ijk);
    const Vec3f p = box_from_scene * Vec3f{float(w.x()), float(w.y()), float(w.z())};
    return p.x < min_m.x || p.y < min_m.y || p.z < min_m.z || p.x > max_m.x || p.y > max_m.y || p.z > max_m.z;
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
  if (options.min_component_triangles <= 1) return report;

  TriangleMesh mesh;
  size_t last_small = SIZE_MAX;
  for (;;) {
    mesh = meshScene(scene);
    const std::vector<size_t> sizes = faceComponentSizes(mesh);
    const ComponentStats stats = meshComponents(mesh, options.min_component_triangles);
    if (report.passes == 0) report.pieces_before = stats.pieces, report.small_pieces_before = stats.small;
    report.pieces_after = stats.pieces;
    report.small_pieces_after = stats.small;
    if (stats.small == 0 || report.passes >= options.max_passes) break;
    // Marching cubes made each face from a cube whose eight voxels were all observed, with its
    // vertices on the cube's edges: without an edge's voxels the cube, and the face, are gone.
    // A voxel may end edges of a small piece and of a kept one: keep it, so that the kept
    // surface loses as little as it can, unless that made no progress last pass.
    std::vector<bool> small(mesh.positions.size(), false);
    for (size_t f = 0; f < mesh.triangles.size(); ++f)
      if (sizes[f] < options.min_component_triangles)
        for (int32_t v : mesh.triangles[f]) small[size_t(v)] = true;
    openvdb::MaskGrid::Ptr cut = edgeVoxels(g, mesh, small, true);
    if (stats.small < last_small) cut->tree().topologyDifference(edgeVoxels(g, mesh, small, false)->tree());
    last_small = stats.small;
    report.piece_voxels += removeMaskedVoxels(g, *cut);
    ++report.passes;
  }
  // What is left of a removed piece's band (voxels away from its surface) is fog without a
  // surface: it would still show in a volume export. Drop every face-connected part of the band
  // that no surface vertex lies on.
  auto surface = edgeVoxels(g, mesh, std::vector<bool>(mesh.positions.size(), true), true);
  openvdb::tree::ValueAccessor<const openvdb::MaskTree> sacc(surface->tree());
  const VoxelComponents parts = voxelComponents(g);
  std::vector<bool> has_surface(parts.parent.size(), false);
  for (const auto* leaf : parts.leaves)
    for (auto it = leaf->cbeginValueOn(); it; ++it)
      if (sacc.isValueOn(it.getCoord())) has_surface[size_t(parts.parent[size_t(*it)])] = true;
  // (maskWhere runs in parallel: plain tree reads, no accessor.)
  auto bare = maskWhere(g, [&](const openvdb::Coord& ijk, const FloatLeaf&, openvdb::Index) {
    return !has_surface[size_t(parts.parent[size_t(parts.ids->getValue(ijk))])];
  });
  report.bare_band_voxels = removeMaskedVoxels(g, *bare);
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
