// Fuzz target: the dataset layouts' JSON camera files (io/dataset_layouts.h): Replica's
// cam_params.json and Open3D's camera-intrinsics.json (Redwood), both parsed from one input.
#include <cmath>
#include <string>

#include "core/error.h"
#include "io/dataset_layouts.h"

namespace {

// What the parsers promise when they return: image sizes of 1 to 100000 and finite numbers.
void checkCamera(const vf::FrameList& list) {
  if (list.expected_width < 1 || list.expected_width > 100000 || list.expected_height < 1 ||
      list.expected_height > 100000)
    std::abort();
  if (!std::isfinite(list.fx) || !std::isfinite(list.fy) || !std::isfinite(list.cx) || !std::isfinite(list.cy))
    std::abort();
  if (list.intrinsics_source.empty()) std::abort();
}

}  // namespace

extern "C" int LLVMFuzzerTestOneInput(const uint8_t* data, size_t size) {
  const std::string text(reinterpret_cast<const char*>(data), size);
  try {
    vf::FrameList list;
    vf::parseReplicaCamParams(text, "cam_params.json", list);
    checkCamera(list);
    if (!(list.depth_units_per_metre > 0) || !std::isfinite(list.depth_units_per_metre)) std::abort();
  } catch (const vf::Error&) {
  }
  try {
    vf::FrameList list;
    vf::parseOpen3dIntrinsics(text, "camera-intrinsics.json", list);
    checkCamera(list);
  } catch (const vf::Error&) {
  }
  return 0;
}
