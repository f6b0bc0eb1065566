#include "io/trajectory_io.h"

#include <cmath>
#include <cstdio>
#include <cstdlib>
#include <fstream>
#include <sstream>

#include "core/atomic_output.h"
#include "core/error.h"
#include "core/text_fields.h"
#include "core/mapped_file.h"
#include "io/image_io.h"

namespace vf {
namespace {

// Splits on blanks, commas and tabs (TUM's associate.py accepts all three).
std::vector<std::string> fields(const std::string& line) {
  std::vector<std::string> out;
  std::string cur;
  for (char c : line) {
    if (c == ' ' || c == '\t' || c == ',' || c == '\r') {
      if (!cur.empty()) out.push_back(cur), cur.clear();
    } else {
      cur += c;
    }
  }
  if (!cur.empty()) out.push_back(cur);
  return out;
}

double number(const std::string& s, const std::string& where) {
  double v = 0;
  if (!parseFiniteDouble(s, v)) throw Error(where + ": '" + s + "' is not a finite number");
  return v;
}

}  // namespace

Trajectory parseTumTrajectory(const std::string& text, const std::string& source) {
  Trajectory trajectory;
  std::istringstream in(text);
  std::string line;
  for (int line_no = 1; std::getline(in, line); ++line_no) {
    const size_t first = line.find_first_not_of(" \t\r");
    if (first == std::string::npos || line[first] == '#') continue;
    const std::string where = source + ":" + std::to_string(line_no);
    const std::vector<std::string> f = fields(line);
    if (f.size() != 8)
      throw Error(where + ": expected 8 values 'timestamp tx ty tz qx qy qz qw', found " +
                  std::to_string(f.size()));
    double v[8];
    for (int i = 0; i < 8; ++i) v[i] = number(f[i], where);
    Eigen::Quaterniond q(v[7], v[4], v[5], v[6]);  // Eigen's constructor order is w, x, y, z
    const double qn = q.norm();
    if (!(qn > 1e-6)) throw Error(where + ": quaternion (qx qy qz qw) has zero length");
    q.coeffs() /= qn;  // files carry 4 decimals; renormalise so the rotation is orthonormal
    StampedPose p;
    p.timestamp = v[0];
    p.T_world_cam.linear() = q.toRotationMatrix();
    p.T_world_cam.translation() = Eigen::Vector3d(v[1], v[2], v[3]);
    trajectory.push_back(p);
  }
  if (trajectory.empty()) throw Error("trajectory " + source + " contains no poses");
  return trajectory;
}

Trajectory readTumTrajectory(const std::string& path) {
  return parseTumTrajectory(readRegularFile(path, "trajectory file", kMaxTextFileBytes), path);
}

std::string formatTumTrajectory(const Trajectory& trajectory) {
  std::string out = "# timestamp tx ty tz qx qy qz qw (camera-to-world, TUM format)\n";
  char line[256];
  for (const StampedPose& p : trajectory) {
    Eigen::Quaterniond q(p.T_world_cam.linear());
    q.normalize();
    if (q.w() < 0) q.coeffs() = -q.coeffs();  // q and -q are one rotation; pick qw >= 0
    const Eigen::Vector3d t = p.T_world_cam.translation();
    std::snprintf(line, sizeof line, "%.6f %.9f %.9f %.9f %.9f %.9f %.9f %.9f\n", p.timestamp, t.x(), t.y(),
                  t.z(), q.x(), q.y(), q.z(), q.w());
    out += line;
  }
  return out;
}

void writeTumTrajectory(const std::string& path, const Trajectory& trajectory) {
  writeFileAtomic(path, formatTumTrajectory(trajectory));
}

}  // namespace vf
