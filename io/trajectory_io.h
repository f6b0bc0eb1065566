#pragma once
// TUM trajectory files: one pose per line, `timestamp tx ty tz qx qy qz qw`, camera-to-world
// (T_world_cam), '#' comments. The format TUM's evaluation scripts and most SLAM systems use.
#include <string>

#include "core/error.h"
#include "core/pose.h"

namespace vf {

// Throws vf::Error "<file>:<line>: ..." for a malformed line (wrong field count, not a number,
// zero quaternion) and naming the file when it is missing or holds no pose.
Trajectory readTumTrajectory(const std::string& path);

// Parses the text of a TUM trajectory; `source` names it in error messages.
Trajectory parseTumTrajectory(const std::string& text, const std::string& source);

// Writes atomically (temp file + rename): timestamps with 6 decimals (microseconds, as TUM),
// translations and quaternions with 9, so a round trip loses nothing a float pose holds.
void writeTumTrajectory(const std::string& path, const Trajectory& trajectory);
// The text writeTumTrajectory writes (a scene records it in its metadata).
std::string formatTumTrajectory(const Trajectory& trajectory);

}  // namespace vf
