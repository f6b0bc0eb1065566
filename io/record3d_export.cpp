#include "io/record3d_export.h"

#include <algorithm>
#include <cstdlib>
#include <filesystem>
#include <fstream>
#include <iterator>
#include <mutex>

#include "core/error.h"
#include "io/frame_list_source.h"
#include "io/image_codec.h"
#include "io/opencv_plugin.h"
#include "core/mapped_file.h"

namespace vf {
namespace fs = std::filesystem;

void enableOpenCvExr() {
  static std::once_flag once;
  std::call_once(once, [] { setenv("OPENCV_IO_ENABLE_OPENEXR", "1", /*overwrite=*/0); });
}

namespace {

std::vector<uint8_t> readBytes(const std::string& path) {
  const std::string bytes = readRegularFile(path, "file", size_t(1) << 30);
  return {bytes.begin(), bytes.end()};
}

// float32 metres from an EXR (OpenCV's decoder, in the OpenCV module).
DepthImage readDepthExr(const std::string& path) {
  enableOpenCvExr();
  const std::vector<uint8_t> bytes = readBytes(path);
  decodeExrHeader(bytes.data(), bytes.size(), path, "EXR depth");  // sizes checked before OpenCV allocates
  return openCvPlugin(path + ": reading EXR depth").decodeExrDepth(bytes, path);
}

// Depth maps are 0.exr .. N-1.exr; one missing in the middle is an error naming it, not the end.
int contiguousExrCount(const fs::path& folder) {
  int last = -1;
  std::error_code ec;
  for (const auto& entry : fs::directory_iterator(folder, ec)) {
    const std::string stem = entry.path().stem().string();
    if (entry.path().extension() != ".exr" || stem.empty() || stem.size() > 9 ||
        stem.find_first_not_of("0123456789") != std::string::npos)
      continue;
    last = std::max(last, std::stoi(stem));
  }
  for (int i = 0; i < last; ++i) {
    const fs::path missing = folder / (std::to_string(i) + ".exr");
    if (!fs::exists(missing))
      throw Error(missing.string() + " is missing, but the export goes on to " + std::to_string(last) +
                  ".exr (a damaged or incompletely copied export)");
  }
  return last + 1;
}

// Confidence: 8-bit single-channel PNG, through the project's codec (size checked first).
std::vector<uint8_t> readConfidence(const std::string& path, int width, int height) {
  const std::vector<uint8_t> bytes = readBytes(path);
  ImageHeader header;
  const Image<uint16_t> conf = decodeGreyPng(bytes.data(), bytes.size(), path, header, "confidence map");
  if (conf.empty() || header.bits != 8 || conf.width() != width || conf.height() != height)
    throw Error(path + ": confidence must be 8-bit single-channel " + std::to_string(width) + "x" +
                std::to_string(height));
  return {conf.data(), conf.data() + size_t(width) * size_t(height)};
}

}  // namespace

Record3dExport::Record3dExport(const std::string& folder, Record3dOptions options)
    : folder_(folder), options_(options) {
  if (options_.min_confidence < 0 || options_.min_confidence > 2)
    throw Error("min_confidence must be 0, 1 or 2, got " + std::to_string(options_.min_confidence));
  const std::string meta_path = (fs::path(folder) / "metadata.json").string();
  if (!fs::exists(meta_path)) throw Error(folder + ": no metadata.json (not a Record3D export)");
  const auto text = readBytes(meta_path);
  meta_ = parseRecord3dMetadata(std::string(text.begin(), text.end()), meta_path);

  if (fs::exists(fs::path(folder) / "depth" / "0.exr")) {
    depth_dir_ = "depth";
    color_dir_ = "rgb";
  } else if (fs::exists(fs::path(folder) / "rgbd" / "0.exr")) {
    depth_dir_ = color_dir_ = "rgbd";
  } else {
    throw Error(folder + ": no depth/0.exr (nor rgbd/0.exr)");
  }
  frame_count_ = contiguousExrCount(fs::path(folder) / depth_dir_);

  const DepthImage first = readDepthExr(depthPath(0));
  if (meta_.depth_width && (meta_.depth_width != first.width() || meta_.depth_height != first.height()))
    throw Error(depthPath(0) + ": depth is " + std::to_string(first.width()) + "x" +
                std::to_string(first.height()) + " but metadata.json says dw x dh = " +
                std::to_string(meta_.depth_width) + "x" + std::to_string(meta_.depth_height));
  meta_.depth_width = first.width();
  meta_.depth_height = first.height();
  if (aspectRatiosDiffer(first.width(), first.height(), meta_.rgb_width, meta_.rgb_height))
    throw Error(depthPath(0) + ": depth is " + std::to_string(first.width()) + "x" + std::to_string(first.height()) +
                " but metadata.json says w x h = " + std::to_string(meta_.rgb_width) + "x" +
                std::to_string(meta_.rgb_height) + ", another aspect ratio; depth and colour cover the same view");
  // Frame 0's colour size against the metadata, before anything is read with it.
  if (fs::exists(colorPath(0))) {
    const std::vector<uint8_t> color = readBytes(colorPath(0));
    const ImageHeader header = decodeImageHeader(color.data(), color.size(), colorPath(0));
    requireRecord3dColorSize(header.width, header.height, meta_, colorPath(0));
  }
  depth_intrinsics_ = scaleRecord3dIntrinsics(meta_, first.width(), first.height());
}

std::string Record3dExport::depthPath(int i) const {
  return (fs::path(folder_) / depth_dir_ / (std::to_string(i) + ".exr")).string();
}
std::string Record3dExport::colorPath(int i) const {
  const fs::path jpg = fs::path(folder_) / color_dir_ / (std::to_string(i) + ".jpg");
  std::error_code ec;
  if (fs::exists(fs::symlink_status(jpg, ec))) return jpg.string();  // a dangling link too: named when read
  return (fs::path(folder_) / color_dir_ / (std::to_string(i) + ".png")).string();
}
std::string Record3dExport::confPath(int i) const {
  return (fs::path(folder_) / "conf" / (std::to_string(i) + ".png")).string();
}

RgbdFrame Record3dExport::load(int index) const {
  if (index < 0 || index >= frame_count_)
    throw Error(folder_ + ": frame " + std::to_string(index) + " out of range (0.." +
                std::to_string(frame_count_ - 1) + ")");
  RgbdFrame frame;
  frame.index = index;
  frame.name = std::to_string(index);
  frame.timestamp = record3dTimestamp(meta_, index);
  frame.depth = readDepthExr(depthPath(index));
  const int w = frame.depth.width(), h = frame.depth.height();
  if (w != meta_.depth_width || h != meta_.depth_height)
    throw Error(depthPath(index) + ": depth is " + std::to_string(w) + "x" + std::to_string(h) +
                ", frame 0 is " + std::to_string(meta_.depth_width) + "x" +
                std::to_string(meta_.depth_height));
  std::vector<uint8_t> conf;
  if (options_.min_confidence > 0 && fs::exists(confPath(index))) conf = readConfidence(confPath(index), w, h);
  filterRecord3dDepth(frame.depth, conf.empty() ? nullptr : conf.data(),
                      options_.min_confidence, options_.depth_units_per_metre);
  if (options_.load_color) {
    const std::string path = colorPath(index);
    if (!fs::exists(path))
      throw Error(path + ": colour image missing" +
                  (fs::is_symlink(path) ? " (a link to " + fs::read_symlink(path).string() + ", which does not exist)"
                                        : std::string()));
    int cw = 0, ch = 0;
    record3dColorSize(meta_, w, h, cw, ch);
    frame.color = decodeColorAtResolution(readBytes(path), meta_, cw, ch, path);
  }
  if (size_t(index) < meta_.T_world_cam.size()) frame.T_world_cam_given = meta_.T_world_cam[index];
  return frame;
}

std::string Record3dExport::description() const {
  return "Record3D EXR+JPG export " + folder_ + ": " + std::to_string(frame_count_) +
         " frames, depth " + std::to_string(meta_.depth_width) + "x" +
         std::to_string(meta_.depth_height);
}

std::unique_ptr<FrameSource> openRecord3d(const std::string& path, Record3dOptions options) {
  const fs::path p(path);
  if (fs::is_directory(p)) {
    if (fs::exists(p / "metadata.json")) return std::make_unique<Record3dExport>(path, options);
    if (fs::exists(p / "metadata") && fs::is_directory(p / "rgbd")) return std::make_unique<Record3dCapture>(path, options);
    throw Error(path + ": a folder without metadata.json (an export) or metadata + rgbd/ (an unzipped .r3d) is not a "
                "Record3D capture");
  }
  if (!fs::exists(p)) throw Error(path + ": no such file or folder");
  if (p.extension() == ".r3d") return std::make_unique<Record3dCapture>(path, options);
  throw Error(path + ": unknown capture format (expected a .r3d file or an export folder)");
}

}  // namespace vf
