// io/undistort.h's remaps against cv::remap on the same maps: identical output, pixel for pixel,
// on real freiburg1 frames and on a lens strong enough that many samples fall outside the image.
#include <gtest/gtest.h>

#include <cstring>
#include <opencv2/imgproc.hpp>

#include "io/tum_dataset.h"
#include "io/undistort.h"
#include "test_data.h"

namespace vf {
namespace {

template <class T>
cv::Mat header(const Image<T>& image, int type) {
  return cv::Mat(image.height(), image.width(), type, const_cast<T*>(image.data()));
}

template <class T>
size_t differingPixels(const Image<T>& ours, const cv::Mat& theirs) {
  size_t n = 0;
  for (int y = 0; y < ours.height(); ++y)
    for (int x = 0; x < ours.width(); ++x)
      n += std::memcmp(&ours(x, y), theirs.ptr(y) + sizeof(T) * size_t(x), sizeof(T)) != 0;
  return n;
}

void expectSameAsOpenCv(const Undistorter& u, const RgbdFrame& raw, const LabelImage& labels) {
  const cv::Mat mx(u.height(), u.width(), CV_32FC1, const_cast<float*>(u.mapX().data()));
  const cv::Mat my(u.height(), u.width(), CV_32FC1, const_cast<float*>(u.mapY().data()));
  cv::Mat depth, color, label;
  cv::remap(header(raw.depth, CV_32FC1), depth, mx, my, cv::INTER_NEAREST, cv::BORDER_CONSTANT, cv::Scalar(0));
  cv::remap(header(raw.color, CV_8UC4), color, mx, my, cv::INTER_LINEAR, cv::BORDER_CONSTANT, cv::Scalar(0, 0, 0, 255));
  cv::remap(header(labels, CV_16UC1), label, mx, my, cv::INTER_NEAREST, cv::BORDER_REPLICATE);
  EXPECT_EQ(differingPixels(u.undistortDepth(raw.depth), depth), 0u);
  EXPECT_EQ(differingPixels(u.undistortColor(raw.color), color), 0u);
  EXPECT_EQ(differingPixels(u.undistortLabels(labels), label), 0u);
}

LabelImage stripes(int width, int height) {
  LabelImage labels(width, height);
  for (int y = 0; y < height; ++y)
    for (int x = 0; x < width; ++x) labels(x, y) = uint16_t((x / 7 + 3 * (y / 5)) % 300);
  return labels;
}

TEST(Undistorter, Freiburg1FramesMatchCvRemapPixelForPixel) {
  VF_REQUIRE_DATA(dir, "tum_fr1_xyz_head100");
  TumOptions raw_options;
  raw_options.undistort = false;
  const TumDataset raw(dir, raw_options);
  const Calibration& c = raw.calibration();
  ASSERT_FALSE(c.distortion.isZero());
  const Undistorter u(raw.depthIntrinsics(), c.distortion);
  for (int i : {0, 37}) {
    SCOPED_TRACE(i);
    const RgbdFrame frame = raw.load(i);
    expectSameAsOpenCv(u, frame, stripes(frame.depth.width(), frame.depth.height()));
  }
}

TEST(Undistorter, AStrongLensWithSamplesBeyondTheBorderMatchesCvRemap) {
  VF_REQUIRE_DATA(dir, "tum_fr3_teddy_head60");
  const TumDataset dataset(dir);
  const RgbdFrame frame = dataset.load(3);
  // Barrel distortion this strong maps the corners of the output far outside the input.
  const Undistorter u(dataset.depthIntrinsics(), Distortion{0.9f, 0.4f, 0.01f, -0.02f, 0.3f});
  int outside = 0;
  for (size_t i = 0; i < u.mapX().size(); ++i)
    outside += u.mapX()[i] < 0 || u.mapY()[i] < 0 || u.mapX()[i] > u.width() - 1 || u.mapY()[i] > u.height() - 1;
  EXPECT_GT(outside, 1000);
  expectSameAsOpenCv(u, frame, stripes(frame.depth.width(), frame.depth.height()));
}

}  // namespace
}  // namespace vf
