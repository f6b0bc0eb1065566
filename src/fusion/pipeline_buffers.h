#pragma once
// The per-frame buffers of a Pipeline (private to src/fusion/pipeline*.cpp): the frame as
// uploaded, its three-level pyramids, the model prediction, and the raycast's tile ranges.
// Allocated once, at the camera's resolution.
#include "core/error.h"
#include "core/intrinsics.h"
#include "fusion/buffer.h"
#include "fusion/pipeline.h"
#include "fusion/raycast_kernels.h"

namespace vf {

constexpr int kPyramidLevels = 3;

template <class T>
ImageView<const T> constView(const ImageBuffer<T>& b) {
  return {b.buffer.data(), b.width, b.height};
}

// Throws vf::Error naming the field when a camera cannot be fused: every stage projects with it.
inline void validateCamera(const Intrinsics& k) {
  auto bad = [](const std::string& field, double value, const std::string& why) {
    throw Error("Intrinsics." + field + " = " + std::to_string(value) + ": " + why);
  };
  constexpr int kMinSide = 8 << (kPyramidLevels - 1), kMaxSide = 16384;  // 8 pixels at the coarsest level
  const std::string sides = "images must be " + std::to_string(kMinSide) + " to " + std::to_string(kMaxSide) +
                            " pixels on a side (a " + std::to_string(kPyramidLevels) + "-level pyramid)";
  if (!(k.width >= kMinSide && k.width <= kMaxSide)) bad("width", k.width, sides);
  if (!(k.height >= kMinSide && k.height <= kMaxSide)) bad("height", k.height, sides);
  // Focal lengths between a 179-degree and a 1-degree field of view; the principal point inside
  // the image. Anything else is a typo, and would send rays off to infinity.
  if (!(k.fx >= 0.005f * float(k.width) && k.fx <= 60.f * float(k.width))) bad("fx", k.fx, "out of range for the image width");
  if (!(k.fy >= 0.005f * float(k.height) && k.fy <= 60.f * float(k.height))) bad("fy", k.fy, "out of range for the image height");
  if (!(k.cx >= 0.f && k.cx <= float(k.width))) bad("cx", k.cx, "the principal point must lie inside the image");
  if (!(k.cy >= 0.f && k.cy <= float(k.height))) bad("cy", k.cy, "the principal point must lie inside the image");
}

struct Pipeline::Buffers {
  ImageBuffer<float> raw_depth;   // as read (metres)
  ImageBuffer<float> static_depth;  // raw depth with dynamic pixels removed: what tracking filters
  // With labels, the filtered depth with the dynamic pixels kept, for integration to vote their
  // class (Pipeline::fusedDepth); depth[0] has them removed.
  ImageBuffer<float> labelled_filtered_depth;
  ImageBuffer<Rgb8> color;       // at the depth size: tracking's intensity, renders
  ImageBuffer<Rgb8> color_full;  // the frame's own colour when larger (iPhone: 720x960 over 192x256), fused as is
  ImageBuffer<uint16_t> labels;
  ImageBuffer<uint8_t> static_mask;
  Buffer<uint8_t> is_dynamic;     // per class id
  ImageBuffer<float> depth[kPyramidLevels];
  ImageBuffer<Vec3f> vertex[kPyramidLevels], normal[kPyramidLevels];              // measured, camera frame
  ImageBuffer<Vec3f> model_vertex[kPyramidLevels], model_normal[kPyramidLevels];  // predicted, world frame
  ImageBuffer<Rgb8> model_color;
  ImageBuffer<float> intensity[kPyramidLevels];        // current frame, grey in [0, 1]
  ImageBuffer<Vec2f> intensity_gradient[kPyramidLevels];
  ImageBuffer<float> model_intensity[kPyramidLevels];  // prediction, -1 where uncoloured
  Buffer<float> range_min, range_max;  // per-tile ray depth bounds

  Buffers(Device d, const Intrinsics& camera) {
    const int w = camera.width, h = camera.height;
    raw_depth.allocate(d, w, h);
    static_depth.allocate(d, w, h);
    labelled_filtered_depth.allocate(d, w, h);
    color.allocate(d, w, h);
    labels.allocate(d, w, h);
    static_mask.allocate(d, w, h);
    is_dynamic.allocate(d, 65536);
    for (int l = 0; l < kPyramidLevels; ++l) {
      depth[l].allocate(d, w >> l, h >> l);
      vertex[l].allocate(d, w >> l, h >> l);
      normal[l].allocate(d, w >> l, h >> l);
      model_vertex[l].allocate(d, w >> l, h >> l);
      model_normal[l].allocate(d, w >> l, h >> l);
      intensity[l].allocate(d, w >> l, h >> l);
      intensity_gradient[l].allocate(d, w >> l, h >> l);
      model_intensity[l].allocate(d, w >> l, h >> l);
    }
    model_color.allocate(d, w, h);
    const size_t full_resolution_tiles =
        size_t((w + kRangeTilePx - 1) / kRangeTilePx) * size_t((h + kRangeTilePx - 1) / kRangeTilePx);
    range_min.allocate(d, full_resolution_tiles);
    range_max.allocate(d, full_resolution_tiles);
  }
};

}  // namespace vf
