// Scene bookkeeping and the dense -> sparse conversion.
#include "vdb/scene.h"

#include <openvdb/tools/Prune.h>
#include <tbb/parallel_for.h>
#include <tbb/parallel_invoke.h>

#include <cmath>
#include <mutex>

#include "core/error.h"
#include "vdb/brick_leaves.h"
#include "vdb/scene_grids.h"

namespace vf {

void ensureOpenVdbInitialized() {
  static std::once_flag once;
  std::call_once(once, [] { openvdb::initialize(); });
}

openvdb::math::Transform::Ptr sceneTransform(float voxel_size_m) {
  auto xform = openvdb::math::Transform::createLinearTransform(double(voxel_size_m));
  xform->postTranslate(openvdb::Vec3d(0.5 * voxel_size_m, 0.5 * voxel_size_m, 0.5 * voxel_size_m));
  return xform;
}

Scene::Scene() : grids_(std::make_unique<SceneGrids>()) {}
Scene::~Scene() = default;
Scene::Scene(Scene&&) noexcept = default;
Scene& Scene::operator=(Scene&&) noexcept = default;

Scene Scene::clone() const {
  Scene out;
  out.meta = meta;
  if (grids_->tsdf) out.grids_->tsdf = grids_->tsdf->deepCopy();
  if (grids_->weight) out.grids_->weight = grids_->weight->deepCopy();
  if (grids_->color) out.grids_->color = grids_->color->deepCopy();
  if (grids_->class_id) out.grids_->class_id = grids_->class_id->deepCopy();
  if (grids_->class_confidence) out.grids_->class_confidence = grids_->class_confidence->deepCopy();
  return out;
}

bool Scene::hasClasses() const { return grids_->class_id != nullptr; }

size_t Scene::activeVoxelCount() const {
  return grids_->tsdf ? size_t(grids_->tsdf->activeVoxelCount()) : 0;
}

namespace {

template <class GridT>
typename GridT::Ptr makeGrid(typename GridT::ValueType background, const char* name,
                             const openvdb::math::Transform::Ptr& xform) {
  auto grid = GridT::create(background);
  grid->setName(name);
  grid->setTransform(xform);
  return grid;
}

// One brick's leaves, built in parallel and inserted into the trees afterwards.
struct LeavesOfBrick {
  openvdb::FloatTree::LeafNodeType* tsdf = nullptr;
  openvdb::FloatTree::LeafNodeType* weight = nullptr;
  openvdb::Vec3STree::LeafNodeType* color = nullptr;
  openvdb::Int32Tree::LeafNodeType* class_id = nullptr;
  openvdb::FloatTree::LeafNodeType* confidence = nullptr;
};

template <class LeafT, class Fill>
LeafT* makeLeaf(const openvdb::Coord& origin, const LeafMask& mask, typename LeafT::ValueType background,
                const Fill& fill) {
  auto* leaf = new LeafT(origin, background, false);
  fill(leaf->buffer().data());
  leaf->setValueMask(mask);
  return leaf;
}

}  // namespace

Scene sceneFromBricks(const BrickVolumeView& v, const SceneMetadata& meta) {
  ensureOpenVdbInitialized();
  if (!(v.voxel_size_m > 0)) throw Error("scene: the brick volume has no voxel size");
  Scene scene;
  scene.meta = meta;
  scene.meta.voxel_size_m = v.voxel_size_m;
  scene.meta.truncation_m = v.truncation_m;

  const auto xform = sceneTransform(v.voxel_size_m);
  const float trunc = v.truncation_m;
  const bool with_classes = v.hasClasses();
  SceneGrids& g = scene.grids();
  g.tsdf = makeGrid<openvdb::FloatGrid>(trunc, kTsdfGridName, xform);
  g.tsdf->setGridClass(openvdb::GRID_LEVEL_SET);
  g.weight = makeGrid<openvdb::FloatGrid>(0.f, kWeightGridName, xform);
  g.color = makeGrid<openvdb::Vec3SGrid>(openvdb::Vec3s(0.f), kColorGridName, xform);
  g.color->setVectorType(openvdb::VEC_INVARIANT);
  if (with_classes) {
    g.class_id = makeGrid<openvdb::Int32Grid>(kSceneUnknownClass, kClassGridName, xform);
    g.class_confidence = makeGrid<openvdb::FloatGrid>(0.f, kClassConfidenceGridName, xform);
  }

  std::vector<LeavesOfBrick> leaves(v.brick_count);
  const BrickLeaves source(v);
  tbb::parallel_for(tbb::blocked_range<size_t>(0, v.brick_count, 64), [&](const auto& range) {
    LeafMask mask;
    for (size_t n = range.begin(); n != range.end(); ++n) {
      if (!source.activeMask(n, mask)) continue;
      const openvdb::Coord origin = source.origin(n);
      LeavesOfBrick& out = leaves[n];
      using FloatLeaf = openvdb::FloatTree::LeafNodeType;
      out.tsdf = makeLeaf<FloatLeaf>(origin, mask, trunc, [&](float* d) { source.tsdf(n, trunc, d); });
      out.weight = makeLeaf<FloatLeaf>(origin, mask, 0.f, [&](float* d) { source.weight(n, d); });
      out.color = makeLeaf<openvdb::Vec3STree::LeafNodeType>(origin, mask, openvdb::Vec3s(0.f),
                                                             [&](openvdb::Vec3s* d) { source.color(n, d); });
      if (!with_classes) continue;
      out.class_id = makeLeaf<openvdb::Int32Tree::LeafNodeType>(origin, mask, kSceneUnknownClass,
                                                                [&](int32_t* d) { source.classId(n, d); });
      out.confidence = makeLeaf<FloatLeaf>(origin, mask, 0.f, [&](float* d) { source.classConfidence(n, d); });
    }
  });

  // Insert the leaves, one grid per task (the trees are independent).
  auto insert = [&](auto& grid, auto member) {
    if (!grid) return;
    auto& tree = grid->tree();
    for (LeavesOfBrick& l : leaves)
      if (l.*member) tree.addLeaf(l.*member);
  };
  tbb::parallel_invoke([&] { insert(g.tsdf, &LeavesOfBrick::tsdf); },
                       [&] { insert(g.weight, &LeavesOfBrick::weight); },
                       [&] { insert(g.color, &LeavesOfBrick::color); },
                       [&] {
                         insert(g.class_id, &LeavesOfBrick::class_id);
                         insert(g.class_confidence, &LeavesOfBrick::confidence);
                       });
  return scene;
}

namespace {

template <class GridT>
size_t removeMasked(GridT& grid, const openvdb::MaskGrid& mask) {
  using LeafT = typename GridT::TreeType::LeafNodeType;
  const auto background = grid.background();
  std::vector<LeafT*> leaves;
  grid.tree().getNodes(leaves);
  std::atomic<size_t> removed{0};
  tbb::parallel_for(tbb::blocked_range<size_t>(0, leaves.size()), [&](const auto& range) {
    size_t local = 0;
    for (size_t n = range.begin(); n != range.end(); ++n) {
      LeafT& leaf = *leaves[n];
      const auto* m = mask.tree().probeConstLeaf(leaf.origin());
      if (!m) continue;
      for (auto it = leaf.beginValueOn(); it; ++it) {
        if (!m->isValueOn(it.pos())) continue;
        leaf.setValueOff(it.pos(), background);
        ++local;
      }
    }
    removed += local;
  });
  openvdb::tools::pruneInactive(grid.tree());
  return removed;
}

}  // namespace

size_t removeMaskedVoxels(SceneGrids& g, const openvdb::MaskGrid& mask) {
  const size_t removed = removeMasked(*g.tsdf, mask);
  if (g.weight) removeMasked(*g.weight, mask);
  if (g.color) removeMasked(*g.color, mask);
  if (g.class_id) removeMasked(*g.class_id, mask);
  if (g.class_confidence) removeMasked(*g.class_confidence, mask);
  return removed;
}

}  // namespace vf
