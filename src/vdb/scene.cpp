// Scene bookkeeping and the dense -> sparse conversion.
#include "vdb/scene.h"

#include <openvdb/tools/Prune.h>
#include <tbb/parallel_for.h>
#include <tbb/parallel_invoke.h>

#include <array>
#include <cmath>
#include <mutex>

#include "core/error.h"
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

// sRGB 8 bit -> linear (IEC 61966-2-1), by table: the conversion runs once per active voxel.
const std::array<float, 256>& srgbToLinearTable() {
  static const std::array<float, 256> table = [] {
    std::array<float, 256> t{};
    for (int i = 0; i < 256; ++i) {
      const float c = i / 255.f;
      t[i] = c <= 0.04045f ? c / 12.92f : std::pow((c + 0.055f) / 1.055f, 2.4f);
    }
    return t;
  }();
  return table;
}

template <class GridT>
typename GridT::Ptr makeGrid(typename GridT::ValueType background, const char* name,
                             const openvdb::math::Transform::Ptr& xform) {
  auto grid = GridT::create(background);
  grid->setName(name);
  grid->setTransform(xform);
  return grid;
}

// Leaves of one brick, built in parallel and inserted into the trees afterwards.
struct BrickLeaves {
  openvdb::FloatTree::LeafNodeType* tsdf = nullptr;
  openvdb::FloatTree::LeafNodeType* weight = nullptr;
  openvdb::Vec3STree::LeafNodeType* color = nullptr;
  openvdb::Int32Tree::LeafNodeType* class_id = nullptr;
  openvdb::FloatTree::LeafNodeType* confidence = nullptr;
};

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

  std::vector<BrickLeaves> leaves(v.brick_count);
  const auto& lin = srgbToLinearTable();
  const float sdf_scale = trunc / kTsdfScale;

  tbb::parallel_for(tbb::blocked_range<size_t>(0, v.brick_count, 64), [&](const auto& range) {
    for (size_t n = range.begin(); n != range.end(); ++n) {
      const size_t base = n * kBrickVoxels;
      // Skip bricks that were touched but where no voxel got weight (e.g. carved free space).
      bool any = false;
      for (int i = 0; i < kBrickVoxels && !any; ++i) any = v.tsdf[base + i].weight > 0;
      if (!any) continue;
      const Vec3i b = v.coords[n];
      const openvdb::Coord origin(b.x * kBrickSize, b.y * kBrickSize, b.z * kBrickSize);
      BrickLeaves& out = leaves[n];
      out.tsdf = new openvdb::FloatTree::LeafNodeType(origin, trunc, false);
      out.weight = new openvdb::FloatTree::LeafNodeType(origin, 0.f, false);
      out.color = new openvdb::Vec3STree::LeafNodeType(origin, openvdb::Vec3s(0.f), false);
      if (with_classes) {
        out.class_id = new openvdb::Int32Tree::LeafNodeType(origin, kSceneUnknownClass, false);
        out.confidence = new openvdb::FloatTree::LeafNodeType(origin, 0.f, false);
      }
      // Brick order is (z, y, x) with x fastest (core/brick_volume.h); OpenVDB leaves store x slowest.
      for (int i = 0; i < kBrickVoxels; ++i) {
        const TsdfVoxel tw = v.tsdf[base + i];
        const uint16_t w = tw.weight;
        if (w == 0) continue;
        const Vec3i local = localVoxelOffset(i);
        const openvdb::Index o = openvdb::Index((local.x << 6) | (local.y << 3) | local.z);
        out.tsdf->setValueOn(o, tw.tsdf * sdf_scale);
        out.weight->setValueOn(o, float(w));
        const Rgb8 c = v.color[base + i];
        out.color->setValueOn(o, openvdb::Vec3s(lin[c.r], lin[c.g], lin[c.b]));
        if (with_classes) {
          const uint32_t vote = v.class_vote[base + i];
          const uint32_t id = voteClass(vote);
          // Confidence 0 means no label ever voted here (the zero-initialised vote), not class 0.
          const bool voted = voteConfidence(vote) > 0 && id != kUnknownClass;
          out.class_id->setValueOn(o, voted ? int32_t(id) : kSceneUnknownClass);
          out.confidence->setValueOn(o, float(voteConfidence(vote)));
        }
      }
    }
  });

  // Insert the leaves, one grid per task (the trees are independent).
  auto insert = [&](auto& grid, auto member) {
    auto& tree = grid->tree();
    for (BrickLeaves& l : leaves)
      if (l.*member) tree.addLeaf(l.*member);
  };
  tbb::parallel_invoke([&] { insert(g.tsdf, &BrickLeaves::tsdf); },
                       [&] { insert(g.weight, &BrickLeaves::weight); },
                       [&] { insert(g.color, &BrickLeaves::color); },
                       [&] {
                         if (with_classes) {
                           insert(g.class_id, &BrickLeaves::class_id);
                           insert(g.class_confidence, &BrickLeaves::confidence);
                         }
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
