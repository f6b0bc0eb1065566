#include "io/record3d.h"

#include <nlohmann/json.hpp>
#include <opencv2/imgproc.hpp>

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <filesystem>
#include <tuple>
#include <fstream>

#include "core/camera_check.h"
#include "core/error.h"
#include "io/frame_list_source.h"
#include "io/image_codec.h"
#include "io/json_fields.h"
#include "core/mapped_file.h"
#include "io/lzfse.h"
#include "io/zip_archive.h"

namespace vf {
namespace {

using nlohmann::json;

// Metadata fields, typed, each error naming the field (io/json_fields.h).
const json& requireKey(const json& j, const char* key, const std::string& source) {
  return jsonMember(j, key, key, source);
}

int positiveInt(const json& j, const char* key, const std::string& source) {
  return jsonInteger(requireKey(j, key, source), 1, 100000, key, source);
}

// [qx, qy, qz, qw, tx, ty, tz] of `field` ("poses[3]"): seven finite numbers.
std::array<double, 7> poseNumbers(const json& p, const std::string& field, const std::string& source) {
  jsonArray(p, 7, field, source);
  std::array<double, 7> v;
  for (size_t i = 0; i < 7; ++i) v[i] = jsonNumber(p[i], field + "[" + std::to_string(i) + "]", source);
  return v;
}

// Two frames at one time (to the microsecond the trajectory is written with) would write a
// trajectory `evaluate` refuses, its two poses at one time.
void requireDistinctTimes(const std::vector<double>& t, const std::string& source) {
  std::vector<size_t> order(t.size());
  for (size_t i = 0; i < t.size(); ++i) order[i] = i;
  auto micro = [&](size_t i) {
    const double us = std::round(t[i] * 1e6);
    return std::isfinite(us) ? us : t[i];
  };
  std::sort(order.begin(), order.end(),
            [&](size_t a, size_t b) { return micro(a) < micro(b) || (micro(a) == micro(b) && a < b); });
  for (size_t k = 1; k < order.size(); ++k)
    if (micro(order[k - 1]) == micro(order[k])) {
      char when[64];
      std::snprintf(when, sizeof when, "%.6f", t[order[k]]);
      throw Error(source + ": 'frameTimestamps[" + std::to_string(order[k - 1]) + "]' and 'frameTimestamps[" +
                  std::to_string(order[k]) + "]' are both " + when + " s; each frame needs its own time");
    }
}

// Why q (x, y, z, w) cannot be a rotation's quaternion, or "": ARKit writes unit quaternions, a
// length far from 1 is a damaged pose.
std::string quaternionProblem(const std::array<double, 7>& p) {
  const double n = Eigen::Quaterniond(p[3], p[0], p[1], p[2]).norm();
  if (n > 0.5 && n < 2.0) return "";
  char text[64];
  std::snprintf(text, sizeof text, "%g", n);
  return std::string("quaternion (qx, qy, qz, qw) has length ") + text + ", not a rotation's 1";
}

// ARKit's world is gravity-aligned, +y up. Record3D writes the poses relative to the first
// frame's ARKit pose and keeps that pose as `initPose`: ARKit = initPose * recorded, so up in
// the recorded frame is initPose's rotation inverted applied to +y. Without `initPose` the
// poses are ARKit's own unless the first is the identity (re-based, gravity lost).
std::optional<Vec3f> record3dWorldUp(const json& j, const Record3dMetadata& m, const std::string& source) {
  if (j.contains("initPose")) {
    const std::array<double, 7> p = poseNumbers(j["initPose"], "initPose", source);
    const std::string problem = quaternionProblem(p);
    if (!problem.empty()) throw Error(source + ": 'initPose' " + problem);
    const Eigen::Quaterniond q(p[3], p[0], p[1], p[2]);
    const Eigen::Vector3d up = q.normalized().toRotationMatrix().transpose() * Eigen::Vector3d::UnitY();
    return Vec3f{float(up.x()), float(up.y()), float(up.z())};
  }
  if (m.T_world_cam.empty()) return std::nullopt;
  // record3dPoseToCamera turned an identity pose into diag(1, -1, -1).
  const Eigen::Matrix3d first_gl = m.T_world_cam.front().linear() * Eigen::Vector3d(1, -1, -1).asDiagonal();
  if ((first_gl - Eigen::Matrix3d::Identity()).norm() < 1e-3) return std::nullopt;
  return Vec3f{0, 1, 0};
}

}  // namespace

Pose record3dPoseToCamera(const std::array<double, 7>& p) {
  const std::string problem = quaternionProblem(p);
  if (!problem.empty()) throw Error("Record3D pose: " + problem);
  Eigen::Quaterniond q(p[3], p[0], p[1], p[2]);  // Eigen's constructor takes w first
  q.normalize();
  Pose T_world_glcam = Pose::Identity();
  T_world_glcam.linear() = q.toRotationMatrix();
  T_world_glcam.translation() = Eigen::Vector3d(p[4], p[5], p[6]);
  // ARKit camera: x right, y up, z backward. Ours: x right, y down, z forward. A point in our
  // camera frame is diag(1, -1, -1) times the same point in ARKit's.
  Pose glcam_from_cam = Pose::Identity();
  glcam_from_cam.linear() = Eigen::Vector3d(1, -1, -1).asDiagonal();
  return T_world_glcam * glcam_from_cam;
}

Record3dMetadata parseRecord3dMetadata(const std::string& text, const std::string& source) {
  json j;
  try {
    j = json::parse(text);
  } catch (const json::exception& e) {
    throw Error(source + ": metadata is not valid JSON (" + e.what() + ")");
  }
  if (!j.is_object()) throw Error(source + ": metadata is not a JSON object");
  Record3dMetadata m;
  m.rgb_width = positiveInt(j, "w", source);
  m.rgb_height = positiveInt(j, "h", source);
  if (j.contains("dw") || j.contains("dh")) {
    m.depth_width = positiveInt(j, "dw", source);
    m.depth_height = positiveInt(j, "dh", source);
  }
  for (const auto& [w, h, what] : {std::tuple{m.rgb_width, m.rgb_height, "w x h"},
                                   std::tuple{m.depth_width, m.depth_height, "dw x dh"}})
    if (uint64_t(w) * uint64_t(h) > kMaxImagePixels)
      throw Error(source + ": metadata " + what + " = " + std::to_string(w) + "x" + std::to_string(h) +
                  " is more than the " + std::to_string(kMaxImagePixels / 1000000) + " Mpx a frame may have");
  // The depth map and the RGB image see the same field of view (K is scaled from one to the
  // other): another aspect ratio means one of the two sizes is wrong, and depth would be read with
  // the wrong row stride.
  if (m.depth_width && aspectRatiosDiffer(m.depth_width, m.depth_height, m.rgb_width, m.rgb_height))
    throw Error(source + ": dw x dh = " + std::to_string(m.depth_width) + "x" + std::to_string(m.depth_height) +
                " and w x h = " + std::to_string(m.rgb_width) + "x" + std::to_string(m.rgb_height) +
                " have different aspect ratios; depth and colour of a capture cover the same view");
  const json& K = jsonArray(requireKey(j, "K", source), 9, "K", source);
  float k[9];
  for (size_t i = 0; i < 9; ++i) k[i] = jsonFloat(K[i], "K[" + std::to_string(i) + "]", source);
  // Column-major: K[0] = fx, K[4] = fy, K[6] = cx, K[7] = cy, K[8] = 1.
  if (k[1] != 0 || k[2] != 0 || k[3] != 0 || k[5] != 0 || k[8] != 1)
    throw Error(source + ": metadata 'K' is not a column-major pinhole matrix [fx, 0, 0, 0, fy, 0, cx, cy, 1]: " +
                K.dump());
  m.fx = k[0], m.fy = k[4], m.cx = k[6], m.cy = k[7];
  // K is for the RGB image: checked here, where its file is known (core/camera_check.h).
  const std::string problem = cameraProblem({m.fx, m.fy, m.cx, m.cy, m.rgb_width, m.rgb_height});
  if (!problem.empty())
    throw Error(source + ": 'K' (for the " + std::to_string(m.rgb_width) + "x" +
                std::to_string(m.rgb_height) + " RGB image): " + problem);
  if (j.contains("fps")) m.fps = jsonNumber(j["fps"], "fps", source);
  if (j.contains("poses")) {
    const json& poses = jsonArray(j["poses"], -1, "poses", source);
    for (size_t i = 0; i < poses.size(); ++i) {
      const std::string field = "poses[" + std::to_string(i) + "]";
      const std::array<double, 7> v = poseNumbers(poses[i], field, source);
      const std::string quaternion = quaternionProblem(v);
      if (!quaternion.empty())
        throw Error(source + ": '" + field + "' (the pose of frame " + std::to_string(i) + "): " + quaternion);
      m.T_world_cam.push_back(record3dPoseToCamera(v));
    }
  }
  if (j.contains("frameTimestamps")) {
    const json& t = jsonArray(j["frameTimestamps"], -1, "frameTimestamps", source);
    for (size_t i = 0; i < t.size(); ++i)
      m.timestamps_s.push_back(jsonNumber(t[i], "frameTimestamps[" + std::to_string(i) + "]", source));
    requireDistinctTimes(m.timestamps_s, source);
  }
  m.world_up = record3dWorldUp(j, m, source);
  if (m.timestamps_s.empty() && !(m.fps > 0))
    throw Error(source + ": metadata has neither 'frameTimestamps' nor a positive 'fps'");
  return m;
}

Intrinsics scaleRecord3dIntrinsics(const Record3dMetadata& m, int width, int height) {
  const float sx = float(width) / float(m.rgb_width);
  const float sy = float(height) / float(m.rgb_height);
  Intrinsics k;
  k.fx = m.fx * sx;
  k.fy = m.fy * sy;
  k.cx = m.cx * sx;
  k.cy = m.cy * sy;
  k.width = width;
  k.height = height;
  return k;
}

double record3dTimestamp(const Record3dMetadata& m, int index) {
  if (index >= 0 && size_t(index) < m.timestamps_s.size()) return m.timestamps_s[size_t(index)];
  return m.fps > 0 ? double(index) / m.fps : 0.0;
}

Trajectory record3dDevicePoses(const Record3dMetadata& meta, int frames) {
  Trajectory poses;
  if (frames <= 0 || meta.T_world_cam.size() < size_t(frames)) return poses;
  for (int i = 0; i < frames; ++i) poses.push_back({record3dTimestamp(meta, i), meta.T_world_cam[size_t(i)]});
  return poses;
}

void requireRecord3dColorSize(int width, int height, const Record3dMetadata& meta, const std::string& what) {
  if (width == meta.rgb_width && height == meta.rgb_height) return;
  throw Error(what + ": the colour image is " + std::to_string(width) + "x" + std::to_string(height) +
              " but the metadata says w x h = " + std::to_string(meta.rgb_width) + "x" +
              std::to_string(meta.rgb_height) + " (its K and the depth size are for that size)");
}

ColorImage decodeColorAtResolution(const std::vector<uint8_t>& encoded, const Record3dMetadata& meta, int width,
                                   int height, const std::string& what) {
  // The project's codec: the header's size is checked before anything is allocated, and a
  // truncated or corrupt image is an error (OpenCV's imdecode returned a grey-ended picture).
  const ImageHeader header = decodeImageHeader(encoded.data(), encoded.size(), what);
  requireRecord3dColorSize(header.width, header.height, meta, what);
  ColorImage decoded = decodeColorImage(encoded.data(), encoded.size(), what, "colour image");
  if (decoded.width() == width && decoded.height() == height) return decoded;
  const cv::Mat full(decoded.height(), decoded.width(), CV_8UC4, decoded.data());
  ColorImage color(width, height);
  cv::Mat small(height, width, CV_8UC4, color.data());
  cv::resize(full, small, small.size(), 0, 0, cv::INTER_AREA);
  return color;
}

void filterRecord3dDepth(DepthImage& depth, const uint8_t* confidence, int min_confidence,
                         float units_per_metre) {
  float* d = depth.data();
  const size_t n = size_t(depth.width()) * size_t(depth.height());
  const float metres_per_unit = 1.f / units_per_metre;
  for (size_t i = 0; i < n; ++i) {
    if (!(std::isfinite(d[i]) && d[i] > 0.f)) d[i] = 0.f;
    if (confidence && confidence[i] < min_confidence) d[i] = 0.f;
    if (units_per_metre != 1.f) d[i] *= metres_per_unit;
  }
}

// Where a capture's entries come from: the .r3d zip, or the folder it was unzipped to.
class Record3dEntries {
 public:
  virtual ~Record3dEntries() = default;
  virtual bool contains(const std::string& entry) const = 0;
  // Thread-safe; throws vf::Error naming the entry when it is missing or over max_bytes.
  virtual std::vector<uint8_t> read(const std::string& entry, uint64_t max_bytes = uint64_t(1) << 30) const = 0;
  virtual std::vector<std::string> entryNames() const = 0;
};

namespace {

std::string depthEntry(int i) { return "rgbd/" + std::to_string(i) + ".depth"; }
std::string confEntry(int i) { return "rgbd/" + std::to_string(i) + ".conf"; }
std::string colorEntry(int i) { return "rgbd/" + std::to_string(i) + ".jpg"; }

class ZipEntries : public Record3dEntries {
 public:
  explicit ZipEntries(const std::string& path) : zip_(path) {}
  bool contains(const std::string& entry) const override { return zip_.contains(entry); }
  std::vector<uint8_t> read(const std::string& entry, uint64_t max_bytes) const override {
    return zip_.read(entry, max_bytes);
  }
  std::vector<std::string> entryNames() const override { return zip_.entryNames(); }

 private:
  ZipArchive zip_;
};

// Entry "rgbd/3.depth" is the file <folder>/rgbd/3.depth.
class FolderEntries : public Record3dEntries {
 public:
  explicit FolderEntries(const std::string& folder) : folder_(folder) {}
  bool contains(const std::string& entry) const override {
    return std::filesystem::is_regular_file(std::filesystem::path(folder_) / entry);
  }
  std::vector<uint8_t> read(const std::string& entry, uint64_t max_bytes) const override {
    const std::filesystem::path path = std::filesystem::path(folder_) / entry;
    std::error_code ec;
    if (!std::filesystem::exists(path, ec)) throw Error(folder_ + ": no file '" + entry + "'");
    const std::string bytes = readRegularFile(path.string(), "capture file", size_t(max_bytes));
    return {bytes.begin(), bytes.end()};
  }
  std::vector<std::string> entryNames() const override {
    std::vector<std::string> names;
    std::error_code ec;
    for (const auto& e : std::filesystem::directory_iterator(std::filesystem::path(folder_) / "rgbd", ec))
      names.push_back("rgbd/" + e.path().filename().string());
    return names;
  }

 private:
  std::string folder_;
};

// Frames are rgbd/0.depth .. rgbd/N-1.depth; one missing in the middle would end the sequence
// there without a word, so it is an error naming the entry.
int contiguousFrameCount(const Record3dEntries& entries, const std::string& path) {
  int last = -1;
  for (const std::string& name : entries.entryNames()) {
    if (name.size() <= 11 || name.compare(0, 5, "rgbd/") != 0 || name.compare(name.size() - 6, 6, ".depth") != 0)
      continue;
    const std::string digits = name.substr(5, name.size() - 11);
    if (digits.empty() || digits.size() > 9 || digits.find_first_not_of("0123456789") != std::string::npos) continue;
    last = std::max(last, std::stoi(digits));
  }
  if (last < 0 || !entries.contains(depthEntry(0))) throw Error(path + ": no 'rgbd/0.depth' entry");
  for (int i = 1; i < last; ++i)
    if (!entries.contains(depthEntry(i)))
      throw Error(path + ": entry '" + depthEntry(i) + "' is missing, but the capture goes on to " + depthEntry(last) +
                  " (a damaged or incompletely copied capture)");
  return last + 1;
}

}  // namespace

Record3dCapture::Record3dCapture(const std::string& path, Record3dOptions options)
    : path_(path), options_(options) {
  if (options_.min_confidence < 0 || options_.min_confidence > 2)
    throw Error("min_confidence must be 0, 1 or 2, got " + std::to_string(options_.min_confidence));
  if (!(options_.depth_units_per_metre > 0 && std::isfinite(options_.depth_units_per_metre)))
    throw Error("depth_units_per_metre must be positive, got " + std::to_string(options_.depth_units_per_metre));
  if (std::filesystem::is_directory(path))
    zip_ = std::make_unique<FolderEntries>(path);
  else
    zip_ = std::make_unique<ZipEntries>(path);
  if (!zip_->contains("metadata"))
    throw Error(path + ": no 'metadata' " + (std::filesystem::is_directory(path) ? "file" : "entry") +
                " (not a Record3D .r3d)");
  const auto text = zip_->read("metadata", 64 << 20);
  meta_ = parseRecord3dMetadata(std::string(text.begin(), text.end()), path + ": metadata");

  frame_count_ = contiguousFrameCount(*zip_, path);
  for (const std::string& name : zip_->entryNames()) {
    if (name.size() > 5 && name.compare(0, 5, "rgbd/") == 0 && name.find(".conf") != std::string::npos)
      has_confidence_ = true;
  }

  if (meta_.depth_width == 0) {
    // No dw/dh: the depth map has the RGB aspect ratio, so width = sqrt(pixels * w / h).
    std::vector<uint8_t> first;
    try {
      first = lzfseDecode(zip_->read(depthEntry(0), 256 << 20));
    } catch (const Error& e) {
      throw Error(path + ": entry '" + depthEntry(0) + "': " + e.what());
    }
    const size_t pixels = first.size() / 4;
    const int w = int(std::lround(std::sqrt(double(pixels) * meta_.rgb_width / meta_.rgb_height)));
    const int h = w > 0 ? int(pixels / size_t(w)) : 0;
    if (first.size() % 4 != 0 || w <= 0 || size_t(w) * size_t(h) != pixels)
      throw Error(path + ": rgbd/0.depth decodes to " + std::to_string(first.size()) +
                  " bytes, not a " + std::to_string(meta_.rgb_width) + ":" +
                  std::to_string(meta_.rgb_height) + " float32 map, and metadata has no dw/dh");
    meta_.depth_width = w;
    meta_.depth_height = h;
  }
  // Frame 0's colour size against the metadata, before anything is read with it.
  if (zip_->contains(colorEntry(0))) {
    const std::vector<uint8_t> jpg = zip_->read(colorEntry(0), 256 << 20);
    const std::string what = path + ": entry '" + colorEntry(0) + "'";
    const ImageHeader header = decodeImageHeader(jpg.data(), jpg.size(), what);
    requireRecord3dColorSize(header.width, header.height, meta_, what);
  }
  depth_intrinsics_ = scaleRecord3dIntrinsics(meta_, meta_.depth_width, meta_.depth_height);
}

Record3dCapture::~Record3dCapture() = default;

void Record3dCapture::decodeEntryInto(const std::string& entry, uint8_t* dst, size_t bytes) const {
  const std::vector<uint8_t> compressed = zip_->read(entry, 256 << 20);  // under the zip mutex
  size_t decoded = 0;
  try {
    decoded = lzfseDecodeInto(compressed.data(), compressed.size(), dst, bytes);  // in parallel
  } catch (const Error& e) {
    throw Error(path_ + ": entry '" + entry + "': " + e.what());
  }
  if (decoded != bytes)
    throw Error(path_ + ": entry '" + entry + "' decodes to " + std::to_string(decoded) +
                " bytes, expected " + std::to_string(bytes) + " (" +
                std::to_string(meta_.depth_width) + "x" + std::to_string(meta_.depth_height) + ")");
}

RgbdFrame Record3dCapture::load(int index) const {
  if (index < 0 || index >= frame_count_)
    throw Error(path_ + ": frame " + std::to_string(index) + " out of range (0.." +
                std::to_string(frame_count_ - 1) + ")");
  const int w = meta_.depth_width, h = meta_.depth_height;
  const size_t pixels = size_t(w) * size_t(h);
  RgbdFrame frame;
  frame.index = index;
  frame.name = std::to_string(index);
  frame.timestamp = record3dTimestamp(meta_, index);
  frame.depth.resize(w, h);
  decodeEntryInto(depthEntry(index), reinterpret_cast<uint8_t*>(frame.depth.data()),
                  pixels * sizeof(float));
  std::vector<uint8_t> confidence;
  if (has_confidence_ && options_.min_confidence > 0) {
    confidence.resize(pixels);
    decodeEntryInto(confEntry(index), confidence.data(), pixels);
  }
  filterRecord3dDepth(frame.depth, confidence.empty() ? nullptr : confidence.data(),
                      options_.min_confidence, options_.depth_units_per_metre);
  if (options_.load_color) {
    const std::string entry = colorEntry(index);
    int cw = 0, ch = 0;
    record3dColorSize(meta_, w, h, cw, ch);
    frame.color = decodeColorAtResolution(zip_->read(entry, 256 << 20), meta_, cw, ch, path_ + ": entry '" + entry + "'");
  }
  if (size_t(index) < meta_.T_world_cam.size()) frame.T_world_cam_given = meta_.T_world_cam[index];
  return frame;
}

std::string Record3dCapture::kind() const {
  return std::filesystem::is_directory(path_) ? "capture folder" : "capture";
}

std::string Record3dCapture::description() const {
  return "Record3D " + kind() + " " + path_ + ": " + std::to_string(frame_count_) + " frames, depth " +
         std::to_string(meta_.depth_width) + "x" + std::to_string(meta_.depth_height) + ", RGB " +
         std::to_string(meta_.rgb_width) + "x" + std::to_string(meta_.rgb_height) +
         (has_confidence_ ? ", min confidence " + std::to_string(options_.min_confidence)
                          : ", no confidence maps");
}

}  // namespace vf
