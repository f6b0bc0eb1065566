#pragma once
// Removes radial-tangential lens distortion (freiburg1 images are not undistorted) with remap
// tables computed once, so that per-frame work is a lookup and concurrent calls share nothing
// mutable. The output camera is the same pinhole K: after remapping, a pixel (u, v) sees the
// ray K^-1 (u, v, 1) exactly.
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
  void checkSize(int width, int height, const char* what) const;
  int width_ = 0, height_ = 0;
  // For each output pixel, where to sample the distorted input (float pixel coordinates).
  std::vector<float> map_x_, map_y_;
};

}  // namespace vf
