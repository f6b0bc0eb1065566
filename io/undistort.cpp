#include "io/undistort.h"

#include <opencv2/imgproc.hpp>
#include <string>

namespace vf {
namespace {

// Wraps host images as cv::Mat headers (no copy).
template <class T>
cv::Mat header(const Image<T>& image, int type) {
  return cv::Mat(image.height(), image.width(), type, const_cast<T*>(image.data()));
}
template <class T>
cv::Mat header(Image<T>& image, int type) {
  return cv::Mat(image.height(), image.width(), type, image.data());
}

}  // namespace

Undistorter::Undistorter(const Intrinsics& K, const Distortion& d) : width_(K.width), height_(K.height) {
  if (!K.valid()) throw Error("undistortion needs valid intrinsics with an image size");
  map_x_.resize(size_t(width_) * height_);
  map_y_.resize(size_t(width_) * height_);
  // Same model and result as cv::initUndistortRectifyMap(K, d, I, K): for each undistorted pixel,
  // project its ray through the Brown-Conrady model to find where the lens put it.
  for (int v = 0; v < height_; ++v)
    for (int u = 0; u < width_; ++u) {
      const double x = (u - double(K.cx)) / K.fx, y = (v - double(K.cy)) / K.fy;
      const double r2 = x * x + y * y;
      const double radial = 1 + r2 * (d.k1 + r2 * (d.k2 + r2 * d.k3));
      const double xd = x * radial + 2 * d.p1 * x * y + d.p2 * (r2 + 2 * x * x);
      const double yd = y * radial + d.p1 * (r2 + 2 * y * y) + 2 * d.p2 * x * y;
      map_x_[size_t(v) * width_ + u] = float(K.fx * xd + K.cx);
      map_y_[size_t(v) * width_ + u] = float(K.fy * yd + K.cy);
    }
}

void Undistorter::checkSize(int width, int height, const char* what) const {
  if (width != width_ || height != height_)
    throw Error(std::string("cannot undistort ") + what + " of " + std::to_string(width) + "x" +
                std::to_string(height) + ": the calibration is for " + std::to_string(width_) + "x" +
                std::to_string(height_));
}

DepthImage Undistorter::undistortDepth(const DepthImage& depth_m) const {
  checkSize(depth_m.width(), depth_m.height(), "depth");
  DepthImage out(width_, height_);
  const cv::Mat mx(height_, width_, CV_32FC1, const_cast<float*>(map_x_.data()));
  const cv::Mat my(height_, width_, CV_32FC1, const_cast<float*>(map_y_.data()));
  cv::Mat dst = header(out, CV_32FC1);
  cv::remap(header(depth_m, CV_32FC1), dst, mx, my, cv::INTER_NEAREST, cv::BORDER_CONSTANT, cv::Scalar(0));
  return out;
}

ColorImage Undistorter::undistortColor(const ColorImage& color) const {
  checkSize(color.width(), color.height(), "colour");
  ColorImage out(width_, height_);
  const cv::Mat mx(height_, width_, CV_32FC1, const_cast<float*>(map_x_.data()));
  const cv::Mat my(height_, width_, CV_32FC1, const_cast<float*>(map_y_.data()));
  cv::Mat dst = header(out, CV_8UC4);
  cv::remap(header(color, CV_8UC4), dst, mx, my, cv::INTER_LINEAR, cv::BORDER_CONSTANT,
            cv::Scalar(0, 0, 0, 255));
  return out;
}

LabelImage Undistorter::undistortLabels(const LabelImage& labels) const {
  checkSize(labels.width(), labels.height(), "label map");
  LabelImage out(width_, height_);
  const cv::Mat mx(height_, width_, CV_32FC1, const_cast<float*>(map_x_.data()));
  const cv::Mat my(height_, width_, CV_32FC1, const_cast<float*>(map_y_.data()));
  cv::Mat dst = header(out, CV_16UC1);
  cv::remap(header(labels, CV_16UC1), dst, mx, my, cv::INTER_NEAREST, cv::BORDER_REPLICATE);
  return out;
}

}  // namespace vf
