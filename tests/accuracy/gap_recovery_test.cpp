// Relocalisation on real frames (issue 41): the shared sequences with a run of frames removed
// (the camera jumps 30-40 cm between two frames) or blanked (a covered lens while the camera
// moves on), reconstructed with the default options through the commands a user runs. Every
// frame from the tenth after the gap on must have a pose again, and the ATE over the poses
// written may be at most 1.5 times the uninterrupted run's over the same frames.
#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <filesystem>
#include <fstream>
#include <set>
#include <sstream>

#include "io/image_io.h"
#include "io/trajectory_io.h"
#include "reliability/cli_harness.h"
#include "test_data.h"

namespace vf {
namespace {

namespace fs = std::filesystem;

struct Gap {
  int first = 0, count = 0;  // the frames (in sequence order) removed or blanked
  bool blank = false;        // true: kept with all-zero depth; false: left out
  int last = 1 << 30;        // frames after this one are left out (a shorter run)
};

double ateRmseCm(const std::string& evaluate_output) {
  const size_t ate = evaluate_output.find("ATE");
  const size_t rmse = evaluate_output.find("rmse", ate);
  if (ate == std::string::npos || rmse == std::string::npos) return -1;
  return std::stod(evaluate_output.substr(rmse + 4));
}

std::vector<std::string> dataLines(const std::string& path, std::vector<std::string>* header) {
  std::ifstream in(path);
  std::vector<std::string> lines;
  for (std::string line; std::getline(in, line);) {
    if (line.empty() || line[0] == '#') {
      if (header) header->push_back(line);
    } else {
      lines.push_back(line);
    }
  }
  return lines;
}

double timestampOf(const std::string& line) { return std::stod(line.substr(0, line.find(' '))); }

void writeLines(const std::string& path, const std::vector<std::string>& header, const std::vector<std::string>& lines) {
  std::ofstream out(path);
  for (const std::string& l : header) out << l << "\n";
  for (const std::string& l : lines) out << l << "\n";
}

// A TUM folder beside `dir` that reads the shared frames, with the gap applied. Returns the
// timestamps of the frames after the gap (the ones that must be tracked again).
std::vector<double> makeTumVariant(const std::string& src, const std::string& dir, const Gap& gap) {
  fs::create_directories(dir + "/depth");
  for (const char* f : {"groundtruth.txt", "camera_intrinsics.txt"}) fs::create_symlink(src + "/" + f, dir + "/" + f);
  fs::create_symlink(src + "/rgb", dir + "/rgb");
  std::vector<std::string> depth_header, rgb_header;
  const std::vector<std::string> depth = dataLines(src + "/depth.txt", &depth_header);
  const std::vector<std::string> rgb = dataLines(src + "/rgb.txt", &rgb_header);
  const int end = std::min(int(depth.size()), gap.last + 1);
  const double gap_from = timestampOf(depth[size_t(gap.first)]) - 0.015;
  const double gap_to = timestampOf(depth[size_t(gap.first + gap.count - 1)]) + 0.015;
  const double run_end = timestampOf(depth[size_t(end - 1)]) + 0.015;
  std::vector<std::string> depth_kept, rgb_kept;
  std::vector<double> after;
  for (int i = 0; i < end; ++i) {
    const std::string& line = depth[size_t(i)];
    const std::string file = line.substr(line.find(' ') + 1);
    const bool in_gap = i >= gap.first && i < gap.first + gap.count;
    if (in_gap && gap.blank) {
      const DepthImage real = readDepthPng(src + "/" + file, kTumDepthUnitsPerMetre);
      writeDepthPng(dir + "/" + file, DepthImage(real.width(), real.height(), 0.f));
    } else if (!in_gap) {
      fs::create_symlink(src + "/" + file, dir + "/" + file);
    }
    if (!in_gap || gap.blank) depth_kept.push_back(line);
    if (i >= gap.first + gap.count) after.push_back(timestampOf(line));
  }
  for (const std::string& line : rgb) {
    const double t = timestampOf(line);
    if (t > run_end || (!gap.blank && t >= gap_from && t <= gap_to)) continue;
    rgb_kept.push_back(line);
  }
  writeLines(dir + "/depth.txt", depth_header, depth_kept);
  writeLines(dir + "/rgb.txt", rgb_header, rgb_kept);
  return after;
}

// The same for a 7-Scenes frame folder (frame-XXXXXX.*, numbered from 0; 30 Hz timestamps).
std::vector<double> makeSevenScenesVariant(const std::string& src, const std::string& dir, const Gap& gap) {
  fs::create_directories(dir);
  fs::create_symlink(src + "/camera-intrinsics.txt", dir + "/camera-intrinsics.txt");
  std::vector<double> after;
  std::string previous_depth;
  for (int i = 0; i <= gap.last; ++i) {
    char stem[32];
    std::snprintf(stem, sizeof stem, "frame-%06d", i);
    const std::string base = src + "/" + stem;
    if (!fs::exists(base + ".depth.png")) break;
    const bool in_gap = i >= gap.first && i < gap.first + gap.count;
    if (in_gap && !gap.blank) continue;
    for (const char* ext : {".color.jpg", ".pose.txt"}) fs::create_symlink(base + ext, dir + "/" + stem + ext);
    if (in_gap) {
      const DepthImage real = readDepthPng(base + ".depth.png", 1000.f);
      writeDepthPng(dir + "/" + stem + ".depth.png", DepthImage(real.width(), real.height(), 0.f), 1000.f);
    } else {
      fs::create_symlink(base + ".depth.png", dir + "/" + stem + ".depth.png");
    }
    // A depth image that repeats the one before byte for byte (the recorder dropped frames) has no
    // pose of its own: it is not counted among the frames that must be tracked again.
    if (i >= gap.first + gap.count && test::fileContent(base + ".depth.png") != previous_depth) after.push_back(i / 30.0);
    previous_depth = test::fileContent(base + ".depth.png");
  }
  return after;
}

struct Outcome {
  double ate_cm = -1;
  Trajectory trajectory;
  std::string report;
};

Outcome reconstruct(const std::string& dataset, const std::string& dir, const std::vector<std::string>& extra = {}) {
  const test::CliRun fused =
      test::runVdbfuse(test::withArgs({"reconstruct", dataset, "-o", dir + "/scene.vdb", "-q"}, extra), 0, 1800);
  EXPECT_EQ(fused.status, 0) << fused.output;
  const test::CliRun evaluated =
      test::runVdbfuse({"evaluate", "--trajectory", dir + "/scene.txt", "--groundtruth", dataset});
  EXPECT_EQ(evaluated.status, 0) << evaluated.output;
  Outcome o;
  o.ate_cm = ateRmseCm(evaluated.output);
  o.trajectory = readTumTrajectory(dir + "/scene.txt");
  o.report = fused.output;
  return o;
}

// The frames from the tenth after the gap on that have no pose in the trajectory written.
std::vector<double> untrackedAfterGap(const std::vector<double>& after, const Trajectory& trajectory) {
  std::vector<double> missing;
  for (size_t i = 9; i < after.size(); ++i) {
    const bool posed = std::any_of(trajectory.begin(), trajectory.end(),
                                   [&](const StampedPose& p) { return std::abs(p.timestamp - after[i]) < 1e-4; });
    if (!posed) missing.push_back(after[i]);
  }
  return missing;
}

void checkRecovery(const std::string& name, const Outcome& uninterrupted, const Outcome& with_gap,
                   const std::vector<double>& after) {
  std::printf("%s: ATE %.3f cm over %zu poses, uninterrupted %.3f cm over %zu\n%s", name.c_str(), with_gap.ate_cm,
              with_gap.trajectory.size(), uninterrupted.ate_cm, uninterrupted.trajectory.size(), with_gap.report.c_str());
  EXPECT_GT(with_gap.ate_cm, 0);
  EXPECT_LE(with_gap.ate_cm, 1.5 * uninterrupted.ate_cm);
  const std::vector<double> missing = untrackedAfterGap(after, with_gap.trajectory);
  EXPECT_TRUE(missing.empty()) << missing.size() << " frames from the tenth after the gap on have no pose, the first at "
                               << (missing.empty() ? 0.0 : missing[0]);
}

TEST(GapRecovery, TumFr1XyzWithThirtyFramesCutOut) {
  VF_REQUIRE_DATA(src, "tum_fr1_xyz_head100");
  const std::string dir = test::tempDir("gap_tum_cut");
  const std::vector<double> after = makeTumVariant(src, dir + "/data", Gap{40, 30});  // the camera jumps 38 cm
  fs::create_directories(dir + "/full");
  fs::create_directories(dir + "/gap");
  checkRecovery("fr1/xyz, frames 40-69 cut", reconstruct(src, dir + "/full"), reconstruct(dir + "/data", dir + "/gap"),
                after);
}

TEST(GapRecovery, TumFr1XyzWithTheLensCoveredForThirtyFrames) {
  VF_REQUIRE_DATA(src, "tum_fr1_xyz_head100");
  const std::string dir = test::tempDir("gap_tum_blank");
  const std::vector<double> after = makeTumVariant(src, dir + "/data", Gap{30, 30, true});  // moves 36 cm meanwhile
  fs::create_directories(dir + "/full");
  fs::create_directories(dir + "/gap");
  checkRecovery("fr1/xyz, frames 30-59 blank", reconstruct(src, dir + "/full"), reconstruct(dir + "/data", dir + "/gap"),
                after);
}

TEST(GapRecovery, SevenScenesKitchenWithFortyFramesCutOut) {
  VF_REQUIRE_DATA(src, "7scenes_redkitchen_head500");
  const std::string dir = test::tempDir("gap_7scenes_cut");
  const std::vector<double> after = makeSevenScenesVariant(src, dir + "/data", Gap{200, 40, false, 299});  // 30 cm
  fs::create_directories(dir + "/full");
  fs::create_directories(dir + "/gap");
  checkRecovery("redkitchen, frames 200-239 cut", reconstruct(src, dir + "/full", {"--max-frames", "300"}),
                reconstruct(dir + "/data", dir + "/gap"), after);
}

TEST(GapRecovery, SevenScenesKitchenWithTheLensCoveredForSixtyFrames) {
  VF_REQUIRE_DATA(src, "7scenes_redkitchen_head500");
  const std::string dir = test::tempDir("gap_7scenes_blank");
  const std::vector<double> after = makeSevenScenesVariant(src, dir + "/data", Gap{250, 60, true, 359});  // 45 cm
  fs::create_directories(dir + "/full");
  fs::create_directories(dir + "/gap");
  checkRecovery("redkitchen, frames 250-309 blank", reconstruct(src, dir + "/full", {"--max-frames", "360"}),
                reconstruct(dir + "/data", dir + "/gap"), after);
}

}  // namespace
}  // namespace vf
