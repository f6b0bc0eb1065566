#pragma once
// Removes radial-tangential lens distortion (freiburg1 images are not undistorted) with remap
// tables computed once, so that per-frame work is a lookup and concurrent calls share nothing
// mutable. The output camera is the same pinhole K: after remapping, a pixel (u, v) sees the
// ray K^-1 (u, v, 1) exactly.
#include <cstdint>
#include <vector>

#include "core/image.h"
#include "core/intrinsics.h"

namespace vf {

class Undistorter {
 public:
  // K gives the image size (K.width x K.height) both images must have.
  Undistorter(const Intrinsics& K, const Distortion& distortion);

  // Nearest neighbour: interpolating depth across an edge invents surfaces between foreground
  // and background (flying pixels), and would mix valid readings with 0 = no reading.
  DepthImage undistortDepth(const DepthImage& depth_m) const;
  // Bilinear: colour may blend, it only has to look right.
  ColorImage undistortColor(const ColorImage& color) const;
  // Nearest neighbour: class ids are categories, never averaged.
  LabelImage undistortLabels(const LabelImage& labels) const;

  int width() const { return width_; }
  int height() const { return height_; }
  // Where each output pixel samples the input (row-major, pixels), for tests against cv::remap.
  const std::vector<float>& mapX() const { return map_x_; }
  const std::vector<float>& mapY() const { return map_y_; }

 private:
  // Where a bilinear sample reads: the input pixel of its top-left tap, its weights (an entry
  // of the 32 x 32 sub-pixel table) and which of its four taps lie inside the image (bits 0-3:
  // top-left, top-right, bottom-left, bottom-right; 0: the whole sample is outside).
  struct BilinearTap {
    int32_t first = 0;
    uint16_t weights = 0;
    uint8_t inside = 0;
  };
  BilinearTap bilinearTap(float x, float y) const;
  void remapBilinearRgba(const Rgb8* src, Rgb8* dst, Rgb8 outside) const;
  void checkSize(int width, int height, const char* what) const;
  int width_ = 0, height_ = 0;
  // For each output pixel, where to sample the distorted input (float pixel coordinates).
  std::vector<float> map_x_, map_y_;
  // The same, resolved once so that a frame's remap is lookups only: the nearest input pixel
  // (-1 outside the image; clamped: the nearest edge pixel instead) and the bilinear taps.
  std::vector<int32_t> nearest_, nearest_clamped_;
  std::vector<BilinearTap> bilinear_;
};

}  // namespace vf
