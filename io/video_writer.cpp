#include "io/video_writer.h"

#include <opencv2/imgproc.hpp>
#include <opencv2/videoio.hpp>

#include <cstdio>
#include <filesystem>

#include "core/error.h"

namespace vf {

struct VideoWriter::Impl {
  std::string path, temp_path;
  int width = 0, height = 0;
  cv::VideoWriter writer;
  bool closed = false;
};

VideoWriter::VideoWriter(const std::string& path, int width, int height, double fps)
    : impl_(std::make_unique<Impl>()) {
  impl_->path = path;
  // Keep the extension so OpenCV picks the container from it.
  const std::filesystem::path p(path);
  impl_->temp_path = (p.parent_path() / ("." + p.stem().string() + ".partial" + p.extension().string())).string();
  impl_->width = width;
  impl_->height = height;
  const int fourcc = cv::VideoWriter::fourcc('m', 'p', '4', 'v');
  if (!impl_->writer.open(impl_->temp_path, fourcc, fps, cv::Size(width, height), true))
    throw Error(path + ": cannot open a video writer (mp4v) for this file");
}

VideoWriter::~VideoWriter() {
  if (!impl_->closed) {
    impl_->writer.release();
    std::remove(impl_->temp_path.c_str());
  }
}

void VideoWriter::write(const ColorImage& frame) {
  if (frame.width() != impl_->width || frame.height() != impl_->height)
    throw Error(impl_->path + ": video frames must all be " + std::to_string(impl_->width) + "x" +
                std::to_string(impl_->height));
  cv::Mat rgba(frame.height(), frame.width(), CV_8UC4, const_cast<Rgb8*>(frame.data()));
  cv::Mat bgr;
  cv::cvtColor(rgba, bgr, cv::COLOR_RGBA2BGR);
  impl_->writer.write(bgr);
}

void VideoWriter::close() {
  impl_->writer.release();
  std::error_code ec;
  std::filesystem::rename(impl_->temp_path, impl_->path, ec);
  if (ec) throw Error(impl_->path + ": cannot move the finished video into place: " + ec.message());
  impl_->closed = true;
}

}  // namespace vf
