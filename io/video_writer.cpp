#include "io/video_writer.h"

#include <algorithm>
#include <cctype>
#include <cstdio>
#include <filesystem>

#include "core/atomic_output.h"
#include "core/error.h"
#include "io/opencv_plugin.h"

namespace vf {

struct VideoWriter::Impl {
  explicit Impl(const std::string& target) : path(target), file(target), temp_path(file.tempPath()) {}
  std::string path;
  AtomicFile file;
  std::string temp_path;
  int width = 0, height = 0;
  std::unique_ptr<VideoSink> writer;
  bool closed = false;
};

void requireVideoWritable(const std::string& path) {
  std::string ext = std::filesystem::path(path).extension().string();
  std::transform(ext.begin(), ext.end(), ext.begin(), [](unsigned char c) { return char(std::tolower(c)); });
  if (ext != ".mp4") throw Error(path + ": a video is written as MP4; name it .mp4");
  AtomicFile probe(path);  // removed again: only whether a writer opens is asked
  const std::unique_ptr<VideoSink> sink = openCvPlugin(path + ": writing a video").openMp4(probe.tempPath(), 64, 64, 30);
  if (!sink)
    throw Error(path + ": this vdbfuse's OpenCV cannot write an MP4 video (mp4v through FFmpeg); leave out the "
                       "video (the PNG renders need no codec)");
  sink->release();
}

VideoWriter::VideoWriter(const std::string& path, int width, int height, double fps)
    : impl_(std::make_unique<Impl>(path)) {
  impl_->width = width;
  impl_->height = height;
  impl_->writer = openCvPlugin(path + ": writing a video").openMp4(impl_->temp_path, width, height, fps);
  if (!impl_->writer) throw Error(path + ": cannot open a video writer (mp4v) for this file");
}

VideoWriter::~VideoWriter() {
  if (!impl_->closed && impl_->writer) impl_->writer->release();  // the AtomicFile removes the temporary
}

void VideoWriter::write(const ColorImage& frame) {
  if (frame.width() != impl_->width || frame.height() != impl_->height)
    throw Error(impl_->path + ": video frames must all be " + std::to_string(impl_->width) + "x" +
                std::to_string(impl_->height));
  impl_->writer->write(frame);
}

void VideoWriter::close() {
  impl_->writer->release();
  impl_->closed = true;
  // OpenCV reports no write errors; an empty file is the one failure that can be seen.
  std::error_code ec;
  if (std::filesystem::file_size(impl_->temp_path, ec) == 0 || ec)
    throw Error(impl_->path + ": the video could not be written (disk full?)");
  impl_->file.commit();
}

}  // namespace vf
