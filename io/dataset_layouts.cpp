#include "io/dataset_layouts.h"

#include <cstdio>

namespace vf {

void applyLayoutOptions(FrameList& list, const LayoutOptions& options) {
  if (options.depth_units_per_metre) {
    char own[64];
    std::snprintf(own, sizeof own, "%g", double(list.depth_units_per_metre));
    list.depth_units_per_metre = *options.depth_units_per_metre;
    list.depth_scale_source = "depth_units_per_metre override; the layout's own is " + std::string(own);
  }
  if (options.intrinsics) {
    const PinholeOverride& k = *options.intrinsics;
    list.fx = k.fx, list.fy = k.fy, list.cx = k.cx, list.cy = k.cy;
    list.intrinsics_source = "the intrinsics override";
    list.expected_width = list.expected_height = 0;
  }
}

}  // namespace vf
