#pragma once
#include <cstddef>
#include <string>

#include "core/math.h"

namespace vf {

// Geometry of the sparse voxel volume (core/brick_volume.h): voxel size and truncation. There is
// no box: bricks are allocated wherever depth reaches, in the world frame (the first camera's,
// or the recorded poses' frame).
struct VolumeSpec {
  float voxel_size_m = 3.0f / 512.0f;  // 5.86 mm: the 512^3-over-3-m voxel KinectFusion set-ups use
  float truncation_m = 0.0f;           // 0 = derived: kDefaultTruncationVox voxels
  size_t max_bricks = 0;               // 0 = as many as memory allows

  static constexpr float kDefaultTruncationVox = 5.0f;
  static constexpr float kMaxTruncationVox = 64.0f;

  float truncationOrDefault() const {
    return truncation_m > 0 ? truncation_m : kDefaultTruncationVox * voxel_size_m;
  }
  // Throws vf::Error naming the field (VolumeSpec.voxel_size_m, ...) and value when unusable.
  void validate() const;
};

}  // namespace vf
