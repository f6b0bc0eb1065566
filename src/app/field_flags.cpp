#include "app/field_flags.h"

#include <cctype>
#include <utility>

namespace vf::app {
namespace {

const std::pair<const char*, const char*> kFieldOptions[] = {
    {"Device", "--device"},
    {"excludeClassVoxels", "--exclude-classes"},
    {"cropToBox", "--crop-box"},
    {"VolumeSpec.voxel_size_m", "--voxel-size-m"},
    {"VolumeSpec.truncation_m", "--truncation-m"},
    {"MeasurementParams.max_depth_m", "--max-depth-m"},
    {"PipelineParams.dynamic_mask_dilation_px", "--mask-dilation-px"},
    {"ReconstructionOptions.max_frames", "--max-frames"},
    {"Intrinsics.fx", "--intrinsics"},
    {"Intrinsics.fy", "--intrinsics"},
    {"Intrinsics.cx", "--intrinsics"},
    {"Intrinsics.cy", "--intrinsics"},
    {"MeshOptions.min_weight", "--min-weight"},
    {"MeshOptions.min_component_triangles", "--min-component"},
};

}  // namespace

std::string withOptionNames(const std::string& message) {
  std::string out = message;
  for (const auto& [field, option] : kFieldOptions) {
    const std::string f = field;
    for (size_t at = out.find(f); at != std::string::npos; at = out.find(f, at + 1)) {
      const size_t end = at + f.size();
      if (end < out.size() && (std::isalnum(static_cast<unsigned char>(out[end])) || out[end] == '_')) continue;
      const std::string inserted = " (" + std::string(option) + ")";
      out.insert(end, inserted);
      at = end + inserted.size() - 1;
    }
  }
  return out;
}

}  // namespace vf::app
