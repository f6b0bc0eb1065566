#include "core/volume_spec.h"

#include <cmath>
#include <cstdio>

#include "core/error.h"

namespace vf {
namespace {

std::string number(float v) {
  char text[32];
  std::snprintf(text, sizeof text, "%g", double(v));
  return text;
}

}  // namespace

void VolumeSpec::validate() const {
  // 0.1 mm .. 1 m: below, a room needs more bricks than any memory; above, nothing is resolved.
  if (!(voxel_size_m >= 1e-4f && voxel_size_m <= 1.0f))
    throw Error("VolumeSpec.voxel_size_m = " + number(voxel_size_m) + ": expected 0.0001 to 1 metre");
  const float trunc = truncationOrDefault();
  if (!(truncation_m >= 0) || !(trunc >= voxel_size_m && trunc <= kMaxTruncationVox * voxel_size_m))
    throw Error("VolumeSpec.truncation_m = " + number(truncation_m) + ": expected 1 to " +
                number(kMaxTruncationVox) + " voxels (" + number(voxel_size_m) + " to " +
                number(kMaxTruncationVox * voxel_size_m) + " m)");
}

}  // namespace vf
