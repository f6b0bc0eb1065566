#pragma once
// The small text files RGB-D datasets keep beside their frames: 4x4 pose matrices (7-Scenes,
// ScanNet), one row-major 4x4 per line (Replica traj.txt), Redwood/Open3D .log trajectories and
// 3x3 or 4x4 intrinsic matrices. Every parser throws vf::Error "<file>:<line>: ..." on bad input.
#include <optional>
#include <string>
#include <vector>

#include "core/pose.h"

namespace vf {

// All numbers of a text file in order (blanks, commas and '#' comment lines ignored); `source`
// names it in errors. "inf"/"nan" are read as numbers, so callers decide what they mean.
std::vector<double> parseNumbers(const std::string& text, const std::string& source);
std::string readTextFile(const std::string& path, size_t max_bytes = size_t(64) << 20);

// A camera-to-world 4x4 from 16 row-major numbers. The rotation block must be a rotation to
// within 1e-2 (datasets store poses rounded, or from a float pipeline) and is re-orthonormalised;
// the last row must be 0 0 0 1. Returns nullopt when all 16 numbers are infinite (ScanNet marks
// frames its tracking lost with -inf). Throws vf::Error naming `source` otherwise, a NaN or a
// partly infinite matrix included (naming the row and column).
std::optional<Pose> poseFromRowMajor(const double* m16, const std::string& source);

// A file holding one 4x4 matrix (7-Scenes frame-XXXXXX.pose.txt, ScanNet pose/N.txt).
std::optional<Pose> readPoseMatrixFile(const std::string& path);

// Replica (NICE-SLAM layout) traj.txt: one row-major 4x4 camera-to-world per non-empty line.
std::vector<Pose> parseReplicaTrajectory(const std::string& text, const std::string& source);

// Redwood / Open3D .log: per pose a line "id id frame" then four rows of the 4x4
// camera-to-world. Returns (the first id, pose) in file order; two poses for one id are an error
// naming both lines.
struct LogEntry {
  int frame = 0;
  Pose T_world_cam = Pose::Identity();
};
std::vector<LogEntry> parseLogTrajectory(const std::string& text, const std::string& source);

// fx, fy, cx, cy from a 3x3 (7-Scenes/3DMatch camera-intrinsics.txt) or 4x4 (ScanNet
// intrinsic_depth.txt) pinhole matrix: zero skew, last row (0 0 1) or (0 0 1 0 / 0 0 0 1).
struct PinholeMatrix {
  float fx = 0, fy = 0, cx = 0, cy = 0;
};
PinholeMatrix parseIntrinsicMatrix(const std::string& text, const std::string& source);

// The files of `folder` named <prefix><1 to 9 digits><suffix> (ScanNet "12.png", Replica
// "depth000012.png", 7-Scenes "frame-000012.depth.png"), sorted by number; digits as written.
// A missing or unreadable folder gives none. Two files of one number ("12.png" beside
// "012.png") are an error naming both (io/frame_order.h).
struct NumberedFile {
  long number = 0;
  std::string digits;
  bool operator<(const NumberedFile& o) const { return number < o.number || (number == o.number && digits < o.digits); }
};
std::vector<NumberedFile> numberedFiles(const std::string& folder, const std::string& prefix, const std::string& suffix);

}  // namespace vf
