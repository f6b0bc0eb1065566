#include "core/volume_spec.h"

#include <cmath>

#include "core/error.h"

namespace vf {

void VolumeSpec::validate() const {
  auto bad = [](const std::string& field, const std::string& value, const std::string& why) {
    throw Error("volume: " + field + " = " + value + " " + why);
  };
  const int dim[3] = {dims.x, dims.y, dims.z};
  for (int d : dim) {
    if (d <= 0 || d % kBrickSize != 0 || d > 4096)
      bad("volume-size", std::to_string(dims.x) + "," + std::to_string(dims.y) + "," +
                             std::to_string(dims.z),
          "must be positive multiples of 8 and at most 4096");
  }
  if (!(voxel_size_m > 0) || !std::isfinite(voxel_size_m))
    bad("voxel-size-m", std::to_string(voxel_size_m), "must be a positive number of metres");
  const float trunc = truncationOrDefault();
  if (!(trunc >= voxel_size_m) || !std::isfinite(trunc))
    bad("truncation-m", std::to_string(trunc), "must be at least one voxel (" +
                                                    std::to_string(voxel_size_m) + " m)");
}

}  // namespace vf
