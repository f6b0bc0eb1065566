#pragma once
#include <string>

#include "core/math.h"

namespace vf {

// Geometry of the dense voxel volume. Voxel (i, j, k) covers the cube whose lowest corner is
// origin_m + (i, j, k) * voxel_size_m; its sample sits at the cube's centre.
struct VolumeSpec {
  Vec3i dims{512, 512, 512};
  float voxel_size_m = 3.0f / 512.0f;
  float truncation_m = 0.0f;  // 0 = derived: kDefaultTruncationVox voxels
  Vec3f origin_m{0, 0, 0};

  static constexpr float kDefaultTruncationVox = 5.0f;
  static constexpr int kBrickSize = 8;  // dims must be multiples of this

  float truncationOrDefault() const {
    return truncation_m > 0 ? truncation_m : kDefaultTruncationVox * voxel_size_m;
  }
  // Throws vf::Error naming the field and value when the spec is unusable.
  void validate() const;
  Vec3f extent_m() const {
    return {dims.x * voxel_size_m, dims.y * voxel_size_m, dims.z * voxel_size_m};
  }
  size_t voxelCount() const { return size_t(dims.x) * size_t(dims.y) * size_t(dims.z); }
};

}  // namespace vf
