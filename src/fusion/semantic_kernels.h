#pragma once
// Keeping dynamic classes (people, ...) out of geometry: a per-pixel mask, dilated so that the
// segmentation's ragged borders do not leak, applied to the depth that ICP and TSDF use.
#include "core/image.h"

namespace vf {

// static_mask = 0 where a pixel within dilation_px (Chebyshev) carries a dynamic class.
struct DynamicMaskKernel {
  ImageView<const uint16_t> labels;
  const uint8_t* is_dynamic;  // indexed by class id, size 65536
  int dilation_px = 0;
  ImageView<uint8_t> static_mask;

  VF_HD void operator()(int i) const {
    const int x = i % labels.width, y = i / labels.width;
    uint8_t keep = 1;
    for (int v = y - dilation_px; v <= y + dilation_px && keep; ++v)
      for (int u = x - dilation_px; u <= x + dilation_px; ++u)
        if (labels.inside(u, v) && is_dynamic[labels(u, v)]) {
          keep = 0;
          break;
        }
    static_mask[i] = keep;
  }
};

// depth_out = depth_in where the mask keeps the pixel, else 0 (no measurement).
struct ApplyMaskKernel {
  ImageView<const float> depth_in;
  ImageView<const uint8_t> static_mask;
  ImageView<float> depth_out;

  VF_HD void operator()(int i) const { depth_out[i] = static_mask[i] ? depth_in[i] : 0.f; }
};

}  // namespace vf
