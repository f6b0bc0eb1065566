#include "io/dataset_text.h"

#include <Eigen/SVD>
#include <algorithm>
#include <cmath>
#include <cstdio>
#include <cstdlib>
#include <filesystem>
#include <fstream>
#include <map>
#include <sstream>

#include "core/error.h"
#include "core/text_fields.h"
#include "core/mapped_file.h"
#include "io/frame_order.h"

namespace vf {
namespace {

// The numbers of one line; throws "<source>:<line>: 'word' is not a number".
std::vector<double> lineNumbers(std::string line, const std::string& where) {
  for (char& c : line)
    if (c == ',' || c == '\t' || c == '\r') c = ' ';
  std::vector<double> out;
  std::istringstream in(line);
  std::string word;
  while (in >> word) {
    double v = 0;
    if (!parseDouble(word, v)) throw Error(where + ": '" + word + "' is not a number");
    out.push_back(v);
  }
  return out;
}

bool isComment(const std::string& line) {
  const size_t first = line.find_first_not_of(" \t\r");
  return first != std::string::npos && line[first] == '#';
}

std::string at(const std::string& source, int line) { return source + ":" + std::to_string(line); }

}  // namespace

std::string readTextFile(const std::string& path, size_t max_bytes) {
  return readRegularFile(path, "text file", max_bytes);
}

std::vector<double> parseNumbers(const std::string& text, const std::string& source) {
  std::istringstream in(text);
  std::string line;
  std::vector<double> out;
  for (int n = 1; std::getline(in, line); ++n) {
    if (isComment(line)) continue;
    const std::vector<double> v = lineNumbers(line, at(source, n));
    out.insert(out.end(), v.begin(), v.end());
  }
  return out;
}

std::optional<Pose> poseFromRowMajor(const double* m, const std::string& source) {
  int infinite = 0, first_bad = -1;
  for (int i = 0; i < 16; ++i) {
    infinite += std::isinf(m[i]) ? 1 : 0;
    if (!std::isfinite(m[i]) && first_bad < 0) first_bad = i;
  }
  if (infinite == 16) return std::nullopt;  // ScanNet's mark of a frame its tracking lost
  if (first_bad >= 0) {
    char value[32];
    std::snprintf(value, sizeof value, "%g", m[first_bad]);
    throw Error(source + ": the pose holds " + value + " at row " + std::to_string(first_bad / 4 + 1) + ", column " +
                std::to_string(first_bad % 4 + 1) + "; a pose must be finite (only a matrix of all -inf, ScanNet's "
                "mark of a lost frame, means no pose)");
  }
  if (m[12] != 0 || m[13] != 0 || m[14] != 0 || std::abs(m[15] - 1) > 1e-9)
    throw Error(source + ": the last row of a 4x4 pose must be 0 0 0 1");
  Eigen::Matrix3d r;
  for (int i = 0; i < 3; ++i)
    for (int j = 0; j < 3; ++j) r(i, j) = m[i * 4 + j];
  const Eigen::Matrix3d off = r.transpose() * r - Eigen::Matrix3d::Identity();
  if (!off.allFinite() || !(off.cwiseAbs().maxCoeff() <= 1e-2) || !(r.determinant() > 0))
    throw Error(source + ": the 3x3 block of the pose is not a rotation");
  // Nearest rotation (SVD): Isometry3d's inverse assumes an orthonormal block.
  const Eigen::JacobiSVD<Eigen::Matrix3d> svd(r, Eigen::ComputeFullU | Eigen::ComputeFullV);
  Pose pose = Pose::Identity();
  pose.linear() = svd.matrixU() * svd.matrixV().transpose();
  pose.translation() = Eigen::Vector3d(m[3], m[7], m[11]);
  return pose;
}

std::optional<Pose> readPoseMatrixFile(const std::string& path) {
  const std::vector<double> v = parseNumbers(readTextFile(path, 1 << 20), path);
  if (v.size() != 16) throw Error(path + ": expected a 4x4 pose (16 numbers), found " + std::to_string(v.size()));
  return poseFromRowMajor(v.data(), path);
}

std::vector<Pose> parseReplicaTrajectory(const std::string& text, const std::string& source) {
  std::istringstream in(text);
  std::string line;
  std::vector<Pose> poses;
  for (int n = 1; std::getline(in, line); ++n) {
    if (isComment(line) || line.find_first_not_of(" \t\r") == std::string::npos) continue;
    const std::vector<double> v = lineNumbers(line, at(source, n));
    if (v.size() != 16) throw Error(at(source, n) + ": expected a row-major 4x4 pose (16 numbers), found " +
                                    std::to_string(v.size()));
    const std::optional<Pose> pose = poseFromRowMajor(v.data(), at(source, n));
    if (!pose) throw Error(at(source, n) + ": the pose is not finite");
    poses.push_back(*pose);
  }
  if (poses.empty()) throw Error(source + ": holds no pose");
  return poses;
}

std::vector<LogEntry> parseLogTrajectory(const std::string& text, const std::string& source) {
  std::istringstream in(text);
  std::string line;
  std::vector<LogEntry> entries;
  std::vector<double> rows;
  std::map<int, int> line_of_frame;  // a second pose for one frame would silently replace the first
  int header_line = 0, frame = 0;
  for (int n = 1; std::getline(in, line); ++n) {
    if (isComment(line) || line.find_first_not_of(" \t\r") == std::string::npos) continue;
    const std::vector<double> v = lineNumbers(line, at(source, n));
    if (header_line == 0) {
      if (v.size() != 3 || v[0] != std::floor(v[0]) || v[0] < 0 || v[0] > 1e8)
        throw Error(at(source, n) + ": expected a '.log' entry header 'id id frame' (3 integers)");
      header_line = n;
      frame = int(v[0]);
      const auto [it, first] = line_of_frame.emplace(frame, n);
      if (!first)
        throw Error(at(source, n) + ": a second pose for frame " + std::to_string(frame) + " (the first is at line " +
                    std::to_string(it->second) + ")");
      rows.clear();
      continue;
    }
    if (v.size() != 4) throw Error(at(source, n) + ": expected a row of the 4x4 pose (4 numbers)");
    rows.insert(rows.end(), v.begin(), v.end());
    if (rows.size() == 16) {
      const std::optional<Pose> pose = poseFromRowMajor(rows.data(), at(source, header_line));
      if (!pose) throw Error(at(source, header_line) + ": the pose is not finite");
      entries.push_back({frame, *pose});
      header_line = 0;
    }
  }
  if (header_line != 0) throw Error(at(source, header_line) + ": the last pose has fewer than 4 rows");
  if (entries.empty()) throw Error(source + ": holds no pose");
  return entries;
}

PinholeMatrix parseIntrinsicMatrix(const std::string& text, const std::string& source) {
  const std::vector<double> v = parseNumbers(text, source);
  const int n = v.size() == 9 ? 3 : v.size() == 16 ? 4 : 0;
  if (n == 0)
    throw Error(source + ": expected a 3x3 or 4x4 intrinsic matrix, found " + std::to_string(v.size()) + " numbers");
  auto k = [&](int r, int c) { return v[size_t(r * n + c)]; };
  bool ok = k(0, 1) == 0 && k(1, 0) == 0 && k(2, 0) == 0 && k(2, 1) == 0 && k(2, 2) == 1;
  if (n == 4) ok = ok && k(0, 3) == 0 && k(1, 3) == 0 && k(2, 3) == 0 && k(3, 0) == 0 && k(3, 1) == 0 &&
                   k(3, 2) == 0 && k(3, 3) == 1;
  if (!ok) throw Error(source + ": not a pinhole matrix [fx 0 cx; 0 fy cy; 0 0 1]");
  if (!(k(0, 0) > 0 && k(1, 1) > 0 && std::isfinite(k(0, 0)) && std::isfinite(k(1, 1)) && std::isfinite(k(0, 2)) &&
        std::isfinite(k(1, 2))))
    throw Error(source + ": the focal lengths must be positive and finite");
  return {float(k(0, 0)), float(k(1, 1)), float(k(0, 2)), float(k(1, 2))};
}

std::vector<NumberedFile> numberedFiles(const std::string& folder, const std::string& prefix, const std::string& suffix) {
  std::vector<std::string> names;
  std::error_code ec;
  for (const auto& entry : std::filesystem::directory_iterator(folder, ec)) {
    const std::string name = entry.path().filename().string();
    if (name.size() <= prefix.size() + suffix.size() || name.compare(0, prefix.size(), prefix) != 0 ||
        name.compare(name.size() - suffix.size(), suffix.size(), suffix) != 0)
      continue;
    const std::string digits = name.substr(prefix.size(), name.size() - prefix.size() - suffix.size());
    if (digits.size() > 9 || digits.find_first_not_of("0123456789") != std::string::npos) continue;
    names.push_back(name);
  }
  // By number, and "1" beside "000001" refused (io/frame_order.h).
  sortByFrameNumber(names, folder);
  std::vector<NumberedFile> out;
  for (const std::string& name : names) {
    const std::string digits = name.substr(prefix.size(), name.size() - prefix.size() - suffix.size());
    out.push_back({std::stol(digits), digits});
  }
  return out;
}

}  // namespace vf
