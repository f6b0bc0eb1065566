#include "io/tum_dataset.h"

#include <algorithm>
#include <cctype>
#include <cmath>
#include <cstdio>
#include <cstdlib>
#include <filesystem>
#include <fstream>
#include <numeric>
#include <sstream>

#include "core/camera_check.h"
#include "core/error.h"
#include "core/text_fields.h"
#include "core/mapped_file.h"
#include "io/trajectory_io.h"

namespace vf {
namespace {

namespace fs = std::filesystem;

std::vector<std::string> splitBlanks(const std::string& line) {
  std::vector<std::string> out;
  std::istringstream in(line);
  std::string word;
  while (in >> word) out.push_back(word);
  return out;
}

bool parseNumber(const std::string& s, double& v) { return parseFiniteDouble(s, v); }

bool isCommentOrBlank(const std::string& line) {
  const size_t first = line.find_first_not_of(" \t\r");
  return first == std::string::npos || line[first] == '#';
}

std::string toLower(std::string s) {
  for (char& c : s) c = char(std::tolower(static_cast<unsigned char>(c)));
  return s;
}

// The comment lines at the top of a TUM list ("# file: 'rgbd_dataset_freiburg1_xyz.bag'").
std::string headerComments(const std::string& path) {
  std::istringstream in(readRegularFile(path, "TUM file list", kMaxTextFileBytes));
  std::string line, out;
  while (std::getline(in, line) && isCommentOrBlank(line)) out += line + "\n";
  return out;
}

std::string seconds(double s) {
  char buf[32];
  std::snprintf(buf, sizeof buf, "%g s", s);
  return buf;
}

std::string tumTimestampText(double t) {
  char buf[64];
  std::snprintf(buf, sizeof buf, "%.6f", t);
  return buf;
}

std::string stem(const std::string& path) { return fs::path(path).stem().string(); }

// "data/rgbd_dataset_freiburg1_xyz/" -> "rgbd_dataset_freiburg1_xyz".
std::string folderName(const std::string& folder) {
  fs::path p = fs::path(folder).lexically_normal();
  if (p.filename().empty()) p = p.parent_path();
  if (p.filename() == "." || p.filename().empty()) p = fs::absolute(p).lexically_normal();
  if (p.filename().empty()) p = p.parent_path();
  return p.filename().string();
}

}  // namespace

PinholeOverride parsePinholeOverride(const std::string& text) {
  std::string spaced = text;
  std::replace(spaced.begin(), spaced.end(), ',', ' ');
  const std::vector<std::string> f = splitBlanks(spaced);
  double v[4];
  bool ok = f.size() == 4 && std::count(text.begin(), text.end(), ',') == 3;
  for (int i = 0; ok && i < 4; ++i) ok = parseNumber(f[size_t(i)], v[i]);
  if (!ok)
    throw Error("--intrinsics '" + text + "': expected four numbers 'fx,fy,cx,cy' in pixels, e.g. 525,525,319.5,239.5");
  if (!(v[0] > 0 && v[1] > 0))
    throw Error("--intrinsics '" + text + "': focal lengths fx and fy must be positive");
  return {float(v[0]), float(v[1]), float(v[2]), float(v[3])};
}

Calibration readCameraIntrinsicsFile(const std::string& path) {
  std::istringstream in(readRegularFile(path, "camera intrinsics file", kMaxTextFileBytes));
  Calibration c;
  c.source = path;
  std::string line;
  int data_lines = 0;
  for (int line_no = 1; std::getline(in, line); ++line_no) {
    if (isCommentOrBlank(line)) continue;
    const std::string where = path + ":" + std::to_string(line_no);
    const std::vector<std::string> f = splitBlanks(line);
    std::vector<double> v(f.size());
    for (size_t i = 0; i < f.size(); ++i)
      if (!parseNumber(f[i], v[i])) throw Error(where + ": '" + f[i] + "' is not a number");
    if (data_lines == 0) {
      if (v.size() != 4 || !(v[0] > 0 && v[1] > 0))
        throw Error(where + ": expected 'fx fy cx cy' (4 numbers, positive focal lengths)");
      c.fx = float(v[0]), c.fy = float(v[1]), c.cx = float(v[2]), c.cy = float(v[3]);
    } else if (data_lines == 1) {
      if (v.size() != 5) throw Error(where + ": expected distortion 'k1 k2 p1 p2 k3' (5 numbers)");
      c.distortion = {float(v[0]), float(v[1]), float(v[2]), float(v[3]), float(v[4])};
    } else {
      throw Error(where + ": unexpected third line; the file holds 'fx fy cx cy' and optionally 'k1 k2 p1 p2 k3'");
    }
    ++data_lines;
  }
  if (data_lines == 0) throw Error(path + ": no 'fx fy cx cy' line found");
  return c;
}

std::optional<Calibration> publishedTumCalibration(const std::string& hint) {
  const std::string h = toLower(hint);
  // "freiburg1" anywhere, or "fr1" as its own token ("tum_fr1_xyz"), not inside another word.
  auto names = [&h](int n) {
    const std::string digit = std::to_string(n);
    if (h.find("freiburg" + digit) != std::string::npos) return true;
    const std::string token = "fr" + digit;
    for (size_t pos = h.find(token); pos != std::string::npos; pos = h.find(token, pos + 1)) {
      const bool start = pos == 0 || !std::isalnum(static_cast<unsigned char>(h[pos - 1]));
      const size_t end = pos + token.size();
      const bool stop = end == h.size() || !std::isalnum(static_cast<unsigned char>(h[end]));
      if (start && stop) return true;
    }
    return false;
  };
  Calibration c;
  if (names(1)) {
    c = {517.306408f, 516.469215f, 318.643040f, 255.313989f, {0.262383f, -0.953104f, -0.005358f, 0.002628f, 1.163314f}, ""};
    c.source = "published freiburg1 calibration";
  } else if (names(2)) {
    c = {520.908620f, 521.007327f, 325.141442f, 249.701764f, {0.231222f, -0.784899f, -0.003257f, -0.000105f, 0.917205f}, ""};
    c.source = "published freiburg2 calibration";
  } else if (names(3)) {
    c = {535.4f, 539.2f, 320.1f, 247.6f, {}, ""};  // freiburg3 images are already undistorted
    c.source = "published freiburg3 calibration";
  } else {
    return std::nullopt;
  }
  return c;
}

std::vector<TimedFile> readTumFileList(const std::string& path) {
  if (!fs::exists(path)) throw Error("cannot open TUM file list " + path + " (expected in a TUM RGB-D folder)");
  std::istringstream in(readRegularFile(path, "TUM file list", kMaxTextFileBytes));
  std::vector<TimedFile> files;
  std::string line;
  for (int line_no = 1; std::getline(in, line); ++line_no) {
    if (isCommentOrBlank(line)) continue;
    const std::vector<std::string> f = splitBlanks(line);
    TimedFile t;
    if (f.size() < 2 || !parseNumber(f[0], t.timestamp))
      throw Error(path + ":" + std::to_string(line_no) + ": expected 'timestamp filename'");
    t.path = f[1];
    t.line = line_no;
    files.push_back(t);
  }
  if (files.empty()) throw Error("TUM file list " + path + " lists no images");
  return files;
}

void requireDistinctTimestamps(const std::vector<TimedFile>& files, const std::string& list) {
  std::vector<size_t> order(files.size());
  std::iota(order.begin(), order.end(), size_t(0));
  // Microseconds, as the lists and the trajectory written are: two times that print alike are one.
  auto micro = [&](size_t i) {
    const double us = std::round(files[i].timestamp * 1e6);
    return std::isfinite(us) ? us : files[i].timestamp;
  };
  std::sort(order.begin(), order.end(),
            [&](size_t a, size_t b) { return micro(a) < micro(b) || (micro(a) == micro(b) && a < b); });
  for (size_t k = 1; k < order.size(); ++k) {
    const size_t a = order[k - 1], b = order[k];  // a listed before b: ties are sorted by index
    if (micro(a) == micro(b))
      throw Error(list + ":" + std::to_string(files[a].line) + " and line " + std::to_string(files[b].line) +
                  " list the same timestamp " + tumTimestampText(files[b].timestamp) +
                  "; each time may be listed once");
  }
}

std::vector<int> nearestInTime(const std::vector<double>& times, const std::vector<double>& candidates,
                               double max_difference_s, bool prefer_last) {
  std::vector<int> order(candidates.size());
  std::iota(order.begin(), order.end(), 0);
  std::sort(order.begin(), order.end(), [&](int a, int b) {
    return candidates[size_t(a)] < candidates[size_t(b)] || (candidates[size_t(a)] == candidates[size_t(b)] && a < b);
  });
  std::vector<double> sorted(order.size());
  for (size_t k = 0; k < order.size(); ++k) sorted[k] = candidates[size_t(order[k])];
  std::vector<int> out(times.size(), -1);
  for (size_t i = 0; i < times.size(); ++i) {
    const double t = times[i];
    const size_t at = size_t(std::lower_bound(sorted.begin(), sorted.end(), t) - sorted.begin());
    // The nearest are just below t and at or above it.
    double best = max_difference_s;
    int chosen = -1;
    auto consider = [&](size_t k) {
      const double d = std::abs(sorted[k] - t);
      const int j = order[k];
      if (d < best || (d == best && (chosen < 0 || (prefer_last ? j > chosen : j < chosen)))) best = d, chosen = j;
    };
    // A run of equal times is sorted by index: its first and last hold both tie rules' choices.
    if (at < sorted.size()) {
      const auto end = std::upper_bound(sorted.begin() + long(at), sorted.end(), sorted[at]);
      consider(at), consider(size_t(end - sorted.begin()) - 1);
    }
    if (at > 0) {
      const auto first = std::lower_bound(sorted.begin(), sorted.begin() + long(at), sorted[at - 1]);
      consider(size_t(first - sorted.begin())), consider(at - 1);
    }
    out[i] = chosen;
  }
  return out;
}

TumDataset::TumDataset(const std::string& folder, TumOptions options)
    : folder_(folder), options_(std::move(options)) {
  if (!fs::is_directory(folder_)) throw Error("TUM folder not found: " + folder_);
  const std::string depth_list = (fs::path(folder_) / "depth.txt").string();
  const std::string rgb_list = (fs::path(folder_) / "rgb.txt").string();
  const std::vector<TimedFile> depth = readTumFileList(depth_list);
  const std::vector<TimedFile> rgb = readTumFileList(rgb_list);

  requireDistinctTimestamps(depth, depth_list);
  requireDistinctTimestamps(rgb, rgb_list);

  std::vector<double> depth_t, rgb_t;
  for (const TimedFile& f : depth) depth_t.push_back(f.timestamp);
  for (const TimedFile& f : rgb) rgb_t.push_back(f.timestamp);
  // Keep depth.txt order (associateTimestamps returns pairs sorted by depth index).
  std::vector<int> partner(depth.size(), -1);
  if (options_.exclusive_color) {
    for (const auto& [d, c] : associateTimestamps(depth_t, rgb_t, options_.max_time_difference_s))
      partner[size_t(d)] = c;
  } else {
    // The nearest, shared or not; of two equally near the one listed later (the rule of the loop
    // over every pair this replaces, kept so that no folder pairs differently).
    partner = nearestInTime(depth_t, rgb_t, options_.max_time_difference_s, /*prefer_last=*/true);
  }
  for (size_t i = 0; i < depth.size(); ++i) {
    if (partner[i] >= 0) {
      frames_.push_back({depth[i], rgb[size_t(partner[i])]});
      continue;
    }
    ++unassociated_;
    char t[32];
    std::snprintf(t, sizeof t, "%.6f", depth[i].timestamp);
    const std::string what = options_.exclusive_color ? "; left out" : "; fused without colour";
    warnings_.push_back("depth frame " + depth[i].path + " (t = " + t + " s) has no colour image within " +
                        seconds(options_.max_time_difference_s) + " in " + rgb_list + what);
    if (!options_.exclusive_color) frames_.push_back({depth[i], TimedFile{}});
  }
  if (frames_.empty())
    throw Error("no depth frame of " + depth_list + " has a colour image within " +
                seconds(options_.max_time_difference_s) + " in " + rgb_list);

  // Calibration, in priority order: user override, the folder's file, the published values.
  const std::string calib_file = (fs::path(folder_) / "camera_intrinsics.txt").string();
  if (options_.intrinsics) {
    const PinholeOverride& o = *options_.intrinsics;
    calibration_ = {o.fx, o.fy, o.cx, o.cy, {}, "--intrinsics"};
  } else if (fs::exists(calib_file)) {
    calibration_ = readCameraIntrinsicsFile(calib_file);
  } else if (auto c = publishedTumCalibration(folderName(folder_))) {
    calibration_ = *c;
  } else if (auto c2 = publishedTumCalibration(headerComments(rgb_list))) {
    calibration_ = *c2;
  } else {
    throw Error("cannot tell the camera of " + folder_ +
                ": no camera_intrinsics.txt, and neither the folder name nor rgb.txt names freiburg1/2/3; "
                "pass --intrinsics fx,fy,cx,cy");
  }

  const DepthImage first_depth = readDepthPng(depthPath(0), options_.depth_units_per_metre);
  int first_colored = 0;
  while (first_colored < size() && frames_[size_t(first_colored)].color.path.empty()) ++first_colored;
  if (first_colored == size())
    throw Error("no depth frame of " + depth_list + " has a colour image within " +
                seconds(options_.max_time_difference_s) + " in " + rgb_list);
  const ColorImage first_color = readColorImage(colorPath(first_colored));
  if (first_color.width() != first_depth.width() || first_color.height() != first_depth.height())
    throw Error("colour image " + colorPath(first_colored) + " is " + std::to_string(first_color.width()) + "x" +
                std::to_string(first_color.height()) + " but depth image " + depthPath(0) + " is " +
                std::to_string(first_depth.width()) + "x" + std::to_string(first_depth.height()) +
                "; TUM depth must be registered to colour at the same size");
  intrinsics_ = {calibration_.fx, calibration_.fy, calibration_.cx, calibration_.cy, first_depth.width(),
                 first_depth.height()};
  const std::string problem = cameraProblem(intrinsics_);
  if (!problem.empty())
    throw Error(calibration_.source + ": " + problem + " (the depth images, e.g. " + depthPath(0) + ", are " +
                std::to_string(first_depth.width()) + "x" + std::to_string(first_depth.height()) + ")");
  if (options_.undistort && !calibration_.distortion.isZero()) undistorter_.emplace(intrinsics_, calibration_.distortion);

  const std::string gt_file = (fs::path(folder_) / "groundtruth.txt").string();
  if (fs::exists(gt_file)) ground_truth_ = readTumTrajectory(gt_file);
  // Each frame's pose looked up once (poseNearTimestamp's rule: the nearest, the first listed of
  // equally near ones), not by a scan of the whole ground truth per frame.
  std::vector<double> frame_t, gt_t;
  for (const Entry& e : frames_) frame_t.push_back(e.depth.timestamp);
  for (const StampedPose& p : ground_truth_) gt_t.push_back(p.timestamp);
  ground_truth_index_ = nearestInTime(frame_t, gt_t, options_.max_time_difference_s, /*prefer_last=*/false);
}

void TumDataset::checkIndex(int index) const {
  if (index < 0 || index >= size())
    throw Error("frame " + std::to_string(index) + " out of range: " + folder_ + " has " + std::to_string(size()) +
                " associated frames");
}

std::string TumDataset::depthPath(int index) const {
  checkIndex(index);
  return (fs::path(folder_) / frames_[size_t(index)].depth.path).string();
}

std::string TumDataset::colorPath(int index) const {
  checkIndex(index);
  const std::string& path = frames_[size_t(index)].color.path;
  return path.empty() ? std::string() : (fs::path(folder_) / path).string();
}

Distortion TumDataset::depthDistortion() const { return undistorter_ ? Distortion{} : calibration_.distortion; }

std::string TumDataset::description() const {
  std::string d = "TUM RGB-D " + folder_ + ": " + std::to_string(size()) + " frames " +
                  std::to_string(intrinsics_.width) + "x" + std::to_string(intrinsics_.height) +
                  ", intrinsics from " + calibration_.source;
  if (undistorter_) d += ", undistorted";
  if (unassociated_)
    d += ", " + std::to_string(unassociated_) +
         (options_.exclusive_color ? " depth frames without colour left out" : " depth frames fused without colour");
  if (!ground_truth_.empty()) d += ", ground truth " + std::to_string(ground_truth_.size()) + " poses";
  return d;
}

std::optional<Pose> TumDataset::groundTruthAt(int index) const {
  checkIndex(index);
  const int at = ground_truth_index_[size_t(index)];
  if (at < 0) return std::nullopt;
  return ground_truth_[size_t(at)].T_world_cam;
}

RgbdFrame TumDataset::load(int index) const {
  checkIndex(index);
  const Entry& e = frames_[size_t(index)];
  RgbdFrame frame;
  frame.index = index;
  frame.timestamp = e.depth.timestamp;
  frame.name = stem(e.depth.path);
  frame.depth = readDepthPng(depthPath(index), options_.depth_units_per_metre);
  if (!e.color.path.empty()) frame.color = readColorImage(colorPath(index));
  if (frame.depth.width() != intrinsics_.width || frame.depth.height() != intrinsics_.height)
    throw Error("depth image " + depthPath(index) + " is " + std::to_string(frame.depth.width()) + "x" +
                std::to_string(frame.depth.height()) + ", the sequence is " + std::to_string(intrinsics_.width) +
                "x" + std::to_string(intrinsics_.height));
  if (!frame.color.empty() && (frame.color.width() != frame.depth.width() || frame.color.height() != frame.depth.height()))
    throw Error("colour image " + colorPath(index) + " is " + std::to_string(frame.color.width()) + "x" +
                std::to_string(frame.color.height()) + " but its depth image " + depthPath(index) + " is " +
                std::to_string(frame.depth.width()) + "x" + std::to_string(frame.depth.height()));
  if (undistorter_) {
    frame.depth = undistorter_->undistortDepth(frame.depth);
    if (!frame.color.empty()) frame.color = undistorter_->undistortColor(frame.color);
  }
  if (options_.attach_groundtruth) frame.T_world_cam_given = groundTruthAt(index);
  return frame;
}

}  // namespace vf
