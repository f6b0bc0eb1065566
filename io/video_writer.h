#pragma once
// MP4 video of rendered frames (OpenCV, through io/opencv_plugin.h). Written to a temporary file beside the target and
// renamed into place by close(), so an interrupted run leaves no half-written video.
#include <memory>
#include <string>

#include "core/image.h"

namespace vf {

// Throws vf::Error naming `path` unless it ends in .mp4 and this build's OpenCV can write an MP4
// (mp4v, through FFmpeg) there: a run checks before its work, not at its first frame.
void requireVideoWritable(const std::string& path);

class VideoWriter {
 public:
  VideoWriter(const std::string& path, int width, int height, double fps);
  ~VideoWriter();  // discards the temporary file unless close() succeeded
  void write(const ColorImage& frame);
  void close();

 private:
  struct Impl;
  std::unique_ptr<Impl> impl_;
};

}  // namespace vf
