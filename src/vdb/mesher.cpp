#include "vdb/mesher.h"

#include <tbb/parallel_for.h>

#include <array>
#include <algorithm>
#include <cmath>

#include "core/error.h"
#include "vdb/marching_cubes_table.h"
#include "vdb/scene_grids.h"

namespace vf {
namespace {

using FloatLeaf = openvdb::FloatTree::LeafNodeType;
using IndexTree = openvdb::Int32Tree;
using IndexLeaf = IndexTree::LeafNodeType;
using FloatAcc = openvdb::tree::ValueAccessor<const openvdb::FloatTree>;
using IndexAcc = openvdb::tree::ValueAccessor<const openvdb::Int32Tree>;
using ColorAcc = openvdb::tree::ValueAccessor<const openvdb::Vec3STree>;

// A leaf's 8^3 voxels plus the one-voxel border on the +x/+y/+z sides: everything a cube
// whose lowest corner lies in the leaf touches, fetched once per leaf.
struct LeafBlock {
  static constexpr int N = 9;
  std::array<float, N * N * N> value;
  std::array<uint8_t, N * N * N> ok;  // observed (active and weight >= min)
  static int at(int x, int y, int z) { return (x * N + y) * N + z; }
};

class Mesher {
 public:
  Mesher(const Scene& scene, const MeshOptions& options)
      : g_(scene.grids()), meta_(scene.meta), options_(options) {
    if (!g_.tsdf || !g_.weight) throw Error("mesh: scene has no tsdf/weight grid");
  }

  TriangleMesh run() {
    g_.tsdf->tree().getNodes(leaves_);
    index_ = std::make_unique<IndexTree>(g_.tsdf->tree(), 0, openvdb::TopologyCopy());
    index_->getNodes(index_leaves_);
    if (index_leaves_.size() != leaves_.size()) throw Error("mesh: inconsistent tsdf topology");
    countVertices();
    placeVertices();
    buildTriangles();
    TriangleMesh mesh = compact();
    computeNormals(mesh);
    return mesh;
  }

 private:
  void fillBlock(size_t n, LeafBlock& block, FloatAcc& tacc,
                 FloatAcc& wacc) const {
    const FloatLeaf& leaf = *leaves_[n];
    const FloatLeaf* wleaf = g_.weight->tree().probeConstLeaf(leaf.origin());
    const openvdb::Coord o = leaf.origin();
    const float min_w = options_.min_weight;
    for (int x = 0; x < 9; ++x)
      for (int y = 0; y < 9; ++y)
        for (int z = 0; z < 9; ++z) {
          const int i = LeafBlock::at(x, y, z);
          if (x < 8 && y < 8 && z < 8) {
            const openvdb::Index p = FloatLeaf::coordToOffset(openvdb::Coord(x, y, z) + o);
            block.value[i] = leaf.getValue(p);
            block.ok[i] = leaf.isValueOn(p) && (min_w <= 0.f || (wleaf && wleaf->getValue(p) >= min_w));
          } else {
            const openvdb::Coord ijk = o + openvdb::Coord(x, y, z);
            float v;
            const bool on = tacc.probeValue(ijk, v);
            block.value[i] = v;
            block.ok[i] = on && (min_w <= 0.f || wacc.getValue(ijk) >= min_w);
          }
        }
  }

  // Bit a of a voxel's edge mask: a vertex on the edge from the voxel along axis a.
  static int edgeMask(const LeafBlock& b, int x, int y, int z) {
    const int i = LeafBlock::at(x, y, z);
    if (!b.ok[i]) return 0;
    const bool in = b.value[i] < 0.f;
    int mask = 0;
    const int step[3] = {LeafBlock::N * LeafBlock::N, LeafBlock::N, 1};
    for (int a = 0; a < 3; ++a) {
      const int j = i + step[a];
      if (b.ok[j] && (b.value[j] < 0.f) != in) mask |= 1 << a;
    }
    return mask;
  }

  void countVertices() {
    counts_.assign(leaves_.size() + 1, 0);
    tbb::parallel_for(tbb::blocked_range<size_t>(0, leaves_.size()), [&](const auto& r) {
      FloatAcc tacc(g_.tsdf->tree()), wacc(g_.weight->tree());
      LeafBlock block;
      for (size_t n = r.begin(); n != r.end(); ++n) {
        fillBlock(n, block, tacc, wacc);
        IndexLeaf& out = *index_leaves_[n];
        int64_t count = 0;
        for (auto it = leaves_[n]->cbeginValueOn(); it; ++it) {
          const openvdb::Coord l = it.getCoord() - leaves_[n]->origin();
          const int mask = edgeMask(block, l.x(), l.y(), l.z());
          out.setValueOnly(it.pos(), mask);
          count += __builtin_popcount(unsigned(mask));
        }
        counts_[n + 1] = count;
      }
    });
    for (size_t n = 1; n < counts_.size(); ++n) counts_[n] += counts_[n - 1];
    if (counts_.back() >= (int64_t(1) << 28)) throw Error("mesh: surface too large (over 2^28 vertices)");
  }

  void placeVertices() {
    const size_t nv = size_t(counts_.back());
    positions_.resize(nv);
    colors_.resize(nv);
    if (g_.class_id) classes_.resize(nv);
    const openvdb::math::Transform& xform = g_.tsdf->transform();
    tbb::parallel_for(tbb::blocked_range<size_t>(0, leaves_.size()), [&](const auto& r) {
      FloatAcc tacc(g_.tsdf->tree());
      std::unique_ptr<ColorAcc> cacc;
      if (g_.color) cacc = std::make_unique<ColorAcc>(g_.color->tree());
      std::unique_ptr<IndexAcc> kacc;
      if (g_.class_id) kacc = std::make_unique<IndexAcc>(g_.class_id->tree());
      for (size_t n = r.begin(); n != r.end(); ++n) {
        IndexLeaf& idx = *index_leaves_[n];
        int32_t next = int32_t(counts_[n]);
        for (auto it = idx.beginValueOn(); it; ++it) {
          const int mask = *it;
          if (!mask) continue;
          it.setValue((next << 3) | mask);
          const openvdb::Coord ijk = it.getCoord();
          const float v0 = tacc.getValue(ijk);
          for (int a = 0; a < 3; ++a) {
            if (!(mask & (1 << a))) continue;
            openvdb::Coord nb = ijk;
            nb[a] += 1;
            const float v1 = tacc.getValue(nb);
            const float t = v0 / (v0 - v1);
            openvdb::Vec3d p(ijk.x(), ijk.y(), ijk.z());
            p[a] += t;
            const openvdb::Vec3d w = xform.indexToWorld(p);
            positions_[next] = {float(w.x()), float(w.y()), float(w.z())};
            if (kacc) classes_[next] = kacc->getValue(t < 0.5f ? ijk : nb);
            Vec3f linear{0, 0, 0};
            if (cacc) {
              const openvdb::Vec3s c = cacc->getValue(ijk) * (1.f - t) + cacc->getValue(nb) * t;
              linear = {c.x(), c.y(), c.z()};
            }
            colors_[next] = surfaceColor(options_.color, meta_.classes, kacc ? classes_[next] : kSceneUnknownClass,
                                         cacc ? &linear : nullptr);
            ++next;
          }
        }
      }
    });
  }

  void buildTriangles() {
    leaf_triangles_.resize(leaves_.size());
    tbb::parallel_for(tbb::blocked_range<size_t>(0, leaves_.size()), [&](const auto& r) {
      FloatAcc tacc(g_.tsdf->tree()), wacc(g_.weight->tree());
      IndexAcc iacc(*index_);
      LeafBlock block;
      for (size_t n = r.begin(); n != r.end(); ++n) {
        fillBlock(n, block, tacc, wacc);
        auto& tris = leaf_triangles_[n];
        const openvdb::Coord o = leaves_[n]->origin();
        for (auto it = leaves_[n]->cbeginValueOn(); it; ++it) {
          const openvdb::Coord l = it.getCoord() - o;
          int inside = 0;
          bool all_ok = true;
          for (int c = 0; c < 8 && all_ok; ++c) {
            const int i = LeafBlock::at(l.x() + (c & 1), l.y() + ((c >> 1) & 1), l.z() + (c >> 2));
            all_ok = block.ok[i];
            inside |= (block.value[i] < 0.f) << c;
          }
          if (!all_ok || inside == 0 || inside == 255) continue;
          const McCase& mc = marchingCubesCase(inside);
          std::array<int32_t, 12> vid;
          vid.fill(-1);
          for (int t = 0; t < mc.triangle_count; ++t) {
            std::array<int32_t, 3> tri;
            for (int k = 0; k < 3; ++k) {
              const int e = mc.edges[size_t(t * 3 + k)];
              if (vid[e] < 0) {
                const int c = kMcEdgeCorner[e], a = kMcEdgeAxis[e];
                const int32_t packed = iacc.getValue(it.getCoord() + openvdb::Coord(c & 1, (c >> 1) & 1, c >> 2));
                vid[e] = (packed >> 3) + __builtin_popcount(unsigned(packed & 7 & ((1 << a) - 1)));
              }
              tri[k] = vid[e];
            }
            tris.push_back(tri);
          }
        }
      }
    });
  }

  // Drops vertices no triangle uses (sign changes at the edge of the observed region).
  TriangleMesh compact() {
    std::vector<int32_t> remap(positions_.size(), -1);
    size_t total = 0;
    for (const auto& t : leaf_triangles_) total += t.size();
    TriangleMesh mesh;
    mesh.triangles.reserve(total);
    for (const auto& tris : leaf_triangles_)
      for (const auto& t : tris) mesh.triangles.push_back(t);
    leaf_triangles_.clear();
    int32_t next = 0;
    for (auto& t : mesh.triangles)
      for (int32_t& v : t) {
        if (remap[v] < 0) remap[v] = next++;
        v = remap[v];
      }
    mesh.positions.resize(size_t(next));
    mesh.colors.resize(size_t(next));
    if (!classes_.empty()) mesh.classes.resize(size_t(next));
    for (size_t v = 0; v < remap.size(); ++v) {
      const int32_t r = remap[v];
      if (r < 0) continue;
      mesh.positions[r] = positions_[v];
      mesh.colors[r] = colors_[v];
      if (!classes_.empty()) mesh.classes[r] = classes_[v];
    }
    return mesh;
  }

  static void computeNormals(TriangleMesh& mesh) {
    mesh.normals.assign(mesh.positions.size(), Vec3f{0, 0, 0});
    for (const auto& t : mesh.triangles) {
      const Vec3f& a = mesh.positions[t[0]];
      const Vec3f n = cross(mesh.positions[t[1]] - a, mesh.positions[t[2]] - a);  // area weighted
      for (int32_t v : t) mesh.normals[v] = mesh.normals[v] + n;
    }
    for (Vec3f& n : mesh.normals) n = normalized(n);
  }

  const SceneGrids& g_;
  const SceneMetadata& meta_;
  MeshOptions options_;
  std::vector<const FloatLeaf*> leaves_;
  std::unique_ptr<IndexTree> index_;
  std::vector<IndexLeaf*> index_leaves_;
  std::vector<int64_t> counts_;  // prefix sums of vertices per leaf
  std::vector<Vec3f> positions_;
  std::vector<Rgb8> colors_;
  std::vector<int32_t> classes_;
  std::vector<std::vector<std::array<int32_t, 3>>> leaf_triangles_;
};

}  // namespace

TriangleMesh meshScene(const Scene& scene, const MeshOptions& options) {
  ensureOpenVdbInitialized();
  return Mesher(scene, options).run();
}

}  // namespace vf
