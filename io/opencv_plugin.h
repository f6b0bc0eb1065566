#pragma once
// What vdbfuse takes from OpenCV's videoio and imgcodecs (MP4 writing, OpenEXR decoding) lives in
// a module of its own, libvdbfuse_opencv.so, loaded on first use. Linked into the program, those
// two libraries and the two hundred they pull in (FFmpeg, GStreamer, GDAL, ...) cost every
// vdbfuse command 0.18 s of dynamic linking before main (three quarters of `vdbfuse info`, 3 %
// of a 100-frame reconstruction) for two features most runs never use.
//
// The module and the program are built together from this tree, so the interface is plain C++;
// the entry point is versioned so that a stale module from another build is refused, not called.
#include <cstdint>
#include <memory>
#include <string>
#include <vector>

#include "core/image.h"

namespace vf {

class VideoSink {
 public:
  virtual ~VideoSink() = default;
  virtual void write(const ColorImage& frame) = 0;  // RGBA, the size given at opening
  virtual void release() = 0;                       // finishes the file
};

class OpenCvPlugin {
 public:
  virtual ~OpenCvPlugin() = default;
  // An MP4 (mp4v) writer on `path`, or null when OpenCV cannot open one.
  virtual std::unique_ptr<VideoSink> openMp4(const std::string& path, int width, int height, double fps) = 0;
  // float32 metres from an EXR's bytes: a single channel as is, the R channel of RGB(A). Throws
  // vf::Error naming `path`.
  virtual DepthImage decodeExrDepth(const std::vector<uint8_t>& bytes, const std::string& path) = 0;
};

// The module, loaded on the first call (from $VDBFUSE_PLUGIN_DIR, ../lib/vdbfuse beside the
// program, the program's folder, or the build tree). Throws vf::Error saying that `feature`
// needs it and where it was looked for.
OpenCvPlugin& openCvPlugin(const std::string& feature);

}  // namespace vf

#define VF_OPENCV_PLUGIN_ENTRY "vdbfuse_opencv_plugin_v1"
extern "C" vf::OpenCvPlugin* vdbfuse_opencv_plugin_v1();
