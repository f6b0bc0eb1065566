#pragma once
// How one fused brick becomes one OpenVDB leaf of each scene grid: the same coordinates, its
// voxels with weight > 0 active, every other value the grid's background. Shared by the
// in-memory conversion (sceneFromBricks) and the streaming writer (writeSceneFromBricks), so
// both give the same grids. Only src/vdb/*.cpp include this.
#include "vdb/openvdb_extern_grids.h"

#include <array>
#include <cmath>

#include "core/brick_volume.h"
#include "vdb/scene.h"

namespace vf {

using LeafMask = openvdb::FloatTree::LeafNodeType::NodeMaskType;
constexpr int kLeafVoxels = int(openvdb::FloatTree::LeafNodeType::SIZE);
static_assert(kLeafVoxels == kBrickVoxels, "a brick must be exactly one OpenVDB leaf");

// sRGB 8 bit -> linear (IEC 61966-2-1), by table: the conversion runs once per active voxel.
inline const std::array<float, 256>& srgbToLinearTable() {
  static const std::array<float, 256> table = [] {
    std::array<float, 256> t{};
    for (int i = 0; i < 256; ++i) {
      const float c = float(i) / 255.f;
      t[size_t(i)] = c <= 0.04045f ? c / 12.92f : std::pow((c + 0.055f) / 1.055f, 2.4f);
    }
    return t;
  }();
  return table;
}

class BrickLeaves {
 public:
  explicit BrickLeaves(const BrickVolumeView& v) : v_(v), sdf_scale_(v.truncation_m / kTsdfScale) {}

  // Leaf origin (index space) of brick n.
  openvdb::Coord origin(size_t n) const {
    const Vec3i b = v_.coords[n];
    return {b.x * kBrickSize, b.y * kBrickSize, b.z * kBrickSize};
  }

  // The voxels of brick n that hold an observation; false when none does (a brick touched only
  // by carved free space, or by a frame that fused nothing there): it becomes no leaf.
  bool activeMask(size_t n, LeafMask& mask) const {
    mask.setOff();
    bool any = false;
    const size_t base = n * kBrickVoxels;
    for (int i = 0; i < kBrickVoxels; ++i)
      if (v_.tsdf[base + size_t(i)].weight > 0) {
        mask.setOn(leafOffset(i));
        any = true;
      }
    return any;
  }

  // One grid's values of brick n in OpenVDB's order; inactive voxels get `background`.
  void tsdf(size_t n, float background, float* out) const {
    fill(n, background, out, [&](size_t k) { return float(v_.tsdf[k].tsdf) * sdf_scale_; });
  }
  void weight(size_t n, float* out) const {
    fill(n, 0.f, out, [&](size_t k) { return float(v_.tsdf[k].weight); });
  }
  void color(size_t n, openvdb::Vec3s* out) const {
    const auto& lin = srgbToLinearTable();
    fill(n, openvdb::Vec3s(0.f), out, [&](size_t k) {
      const Rgb8 c = v_.color[k];
      return openvdb::Vec3s(lin[c.r], lin[c.g], lin[c.b]);
    });
  }
  void classId(size_t n, int32_t* out) const {
    fill(n, int32_t(kSceneUnknownClass), out, [&](size_t k) {
      const uint32_t vote = v_.class_vote[k];
      const uint32_t id = voteClass(vote);
      // Confidence 0 means no label ever voted here (the zero-initialised vote), not class 0.
      return voteConfidence(vote) > 0 && id != kUnknownClass ? int32_t(id) : int32_t(kSceneUnknownClass);
    });
  }
  void classConfidence(size_t n, float* out) const {
    fill(n, 0.f, out, [&](size_t k) { return float(voteConfidence(v_.class_vote[k])); });
  }

 private:
  // Brick order is (z, y, x) with x fastest (core/brick_volume.h); OpenVDB leaves store x slowest.
  static openvdb::Index leafOffset(int brick_local) {
    const Vec3i l = localVoxelOffset(brick_local);
    return openvdb::Index((l.x << 6) | (l.y << 3) | l.z);
  }

  template <class T, class Value>
  void fill(size_t n, T background, T* out, const Value& value) const {
    const size_t base = n * kBrickVoxels;
    for (int i = 0; i < kBrickVoxels; ++i) {
      const size_t k = base + size_t(i);
      out[leafOffset(i)] = v_.tsdf[k].weight > 0 ? value(k) : background;
    }
  }

  const BrickVolumeView& v_;
  float sdf_scale_;
};

}  // namespace vf
