// libvdbfuse_opencv.so: io/opencv_plugin.h on OpenCV (not part of vf_io; io/CMakeLists.txt).
#include <opencv2/core/utils/logger.hpp>
#include <opencv2/imgcodecs.hpp>
#include <opencv2/imgproc.hpp>
#include <opencv2/videoio.hpp>

#include "core/error.h"
#include "io/opencv_plugin.h"

namespace vf {
namespace {

class OpenCvVideo : public VideoSink {
 public:
  // FFmpeg only: with any backend, a file FFmpeg refused went on to GStreamer, whose warnings
  // and OpenCV's assertion text reached the user. OpenCV's exceptions stay in here.
  bool open(const std::string& path, int width, int height, double fps) {
    try {
      return writer_.open(path, cv::CAP_FFMPEG, cv::VideoWriter::fourcc('m', 'p', '4', 'v'), fps,
                          cv::Size(width, height), true);
    } catch (const cv::Exception&) {
      return false;
    }
  }
  void write(const ColorImage& frame) override {
    const cv::Mat rgba(frame.height(), frame.width(), CV_8UC4, const_cast<Rgb8*>(frame.data()));
    try {
      cv::cvtColor(rgba, bgr_, cv::COLOR_RGBA2BGR);
      writer_.write(bgr_);
    } catch (const cv::Exception& e) {
      throw Error(std::string("the video writer failed: ") + e.err);
    }
  }
  void release() override {
    try {
      writer_.release();
    } catch (const cv::Exception&) {  // an unfinished file: the caller sees it empty or short
    }
  }

 private:
  cv::VideoWriter writer_;
  cv::Mat bgr_;
};

class OpenCvModule : public OpenCvPlugin {
 public:
  std::unique_ptr<VideoSink> openMp4(const std::string& path, int width, int height, double fps) override {
    auto video = std::make_unique<OpenCvVideo>();
    if (!video->open(path, width, height, fps)) return nullptr;
    return video;
  }

  DepthImage decodeExrDepth(const std::vector<uint8_t>& bytes, const std::string& path) override {
    const cv::Mat raw(1, int(bytes.size()), CV_8UC1, const_cast<uint8_t*>(bytes.data()));
    cv::Mat m = cv::imdecode(raw, cv::IMREAD_UNCHANGED);
    if (m.empty()) throw Error(path + ": cannot read EXR depth (missing, corrupt, or OpenCV built without OpenEXR)");
    if (m.depth() != CV_32F)
      throw Error(path + ": EXR depth must be 32-bit float, got OpenCV depth " + std::to_string(m.depth()));
    if (m.channels() > 1) {  // OpenCV returns BGR(A): the depth is R
      cv::Mat channel;
      cv::extractChannel(m, channel, 2 < m.channels() ? 2 : 0);
      m = channel;
    }
    DepthImage depth(m.cols, m.rows);
    for (int y = 0; y < m.rows; ++y) {
      const float* row = m.ptr<float>(y);
      for (int x = 0; x < m.cols; ++x) depth(x, y) = row[x];
    }
    return depth;
  }
};

}  // namespace
}  // namespace vf

extern "C" vf::OpenCvPlugin* vdbfuse_opencv_plugin_v1() {
  // OpenCV's own log lines ("[ WARN:0@0.1] global cap_gstreamer.cpp ...") are not for the user:
  // what fails comes back as a null writer or a vf::Error that names the file.
  cv::utils::logging::setLogLevel(cv::utils::logging::LOG_LEVEL_SILENT);
  static vf::OpenCvModule module;
  return &module;
}
