#pragma once
// A TUM RGB-D folder (rgb/, depth/, rgb.txt, depth.txt, optional groundtruth.txt and
// camera_intrinsics.txt) as a FrameSource. Depth frames drive the sequence; each is paired with
// the colour image nearest in time, as TUM's associate.py does.
#include <optional>
#include <string>
#include <vector>

#include "core/frame.h"
#include "io/image_io.h"
#include "io/trajectory_metrics.h"
#include "io/undistort.h"

namespace vf {

// Pinhole parameters a user gives on the command line (--intrinsics fx,fy,cx,cy).
struct PinholeOverride {
  float fx = 0, fy = 0, cx = 0, cy = 0;
};
// Parses "fx,fy,cx,cy" (blanks allowed, 4 positive finite numbers) or throws vf::Error saying
// what is expected.
PinholeOverride parsePinholeOverride(const std::string& text);

// Pinhole + distortion of a camera, and where they came from (reported to the user).
struct Calibration {
  float fx = 0, fy = 0, cx = 0, cy = 0;
  Distortion distortion;
  std::string source;
};
// camera_intrinsics.txt: first non-comment line "fx fy cx cy", an optional second non-comment
// line "k1 k2 p1 p2 k3". Throws vf::Error with file:line when a line is malformed.
Calibration readCameraIntrinsicsFile(const std::string& path);
// The published calibration of freiburg1/2/3 when `hint` names one ("freiburg2", "fr2_..."),
// else nullopt. Values of the TUM "file formats" page (ORB-SLAM2 TUM1/2/3.yaml precision).
std::optional<Calibration> publishedTumCalibration(const std::string& hint);

// One line of rgb.txt / depth.txt.
struct TimedFile {
  double timestamp = 0;
  std::string path;  // as written in the list, relative to the folder
  int line = 0;      // in the list, for messages
};
// Reads a TUM file list ('#' comments); throws vf::Error naming the file when it is missing,
// malformed (with its line) or empty.
std::vector<TimedFile> readTumFileList(const std::string& path);

// Throws vf::Error naming `list` and both lines when two entries share a timestamp (to the
// microsecond a TUM file carries): a repeated depth.txt line would fuse one frame twice and write
// a trajectory with two poses at one time, which `evaluate` refuses; in rgb.txt it makes the
// pairing a guess. (One file at two times is left alone: it is two frames, however odd.)
void requireDistinctTimestamps(const std::vector<TimedFile>& files, const std::string& list);

// For each of `times`, the index into `candidates` of the one nearest in time within
// max_difference_s (a difference of exactly max_difference_s included), -1 when none; among
// equally near candidates the one listed last (`prefer_last`) or first. Sorted lists and a binary
// search: n log n, where every pair cost minutes on long lists.
std::vector<int> nearestInTime(const std::vector<double>& times, const std::vector<double>& candidates,
                               double max_difference_s, bool prefer_last);

struct TumOptions {
  std::optional<PinholeOverride> intrinsics;  // wins over every other source; no distortion
  float depth_units_per_metre = kTumDepthUnitsPerMetre;
  bool undistort = true;  // remove the lens distortion when it is non-zero (freiburg1)
  double max_time_difference_s = kTumMaxTimeDifference_s;
  // associate.py's pairing: each colour image serves at most one depth frame and depth frames
  // left without a partner are dropped. Off (the default), every depth frame takes the nearest
  // colour image within max_time_difference_s, shared or not, and a depth frame with none is
  // still fused, without colour: a SLAM run should not lose frames to a pairing convention.
  bool exclusive_color = false;
  // Attach the ground-truth pose nearest in time (within max_time_difference_s) to each frame
  // as RgbdFrame::T_world_cam_given.
  bool attach_groundtruth = true;
};

class TumDataset : public FrameSource {
 public:
  // Reads the lists, associates, picks the calibration and reads the first depth and colour
  // image for the size; throws vf::Error naming the file on any problem.
  explicit TumDataset(const std::string& folder, TumOptions options = {});

  int size() const override { return int(frames_.size()); }
  // Thread-safe: reads only members fixed by the constructor.
  RgbdFrame load(int index) const override;
  Intrinsics depthIntrinsics() const override { return intrinsics_; }
  // Distortion of the delivered frames: zero when they are undistorted (the default).
  Distortion depthDistortion() const override;
  std::string description() const override;
  Trajectory groundTruth() const override { return ground_truth_; }

  // Distortion of the raw images, from the calibration (also when frames are undistorted).
  const Calibration& calibration() const { return calibration_; }
  // Ground-truth pose nearest to the frame's depth timestamp within max_time_difference_s.
  std::optional<Pose> groundTruthAt(int index) const;
  double timestamp(int index) const { return frames_.at(size_t(index)).depth.timestamp; }
  std::string depthPath(int index) const;
  std::string colorPath(int index) const;

  // One line per depth frame without a colour image within max_time_difference_s: fused
  // without colour, or (exclusive_color) left out as associate.py does.
  const std::vector<std::string>& warnings() const { return warnings_; }
  int unassociatedCount() const { return unassociated_; }

 private:
  struct Entry {
    TimedFile depth;
    TimedFile color;
  };
  void checkIndex(int index) const;
  std::string folder_;
  TumOptions options_;
  std::vector<Entry> frames_;
  Calibration calibration_;
  Intrinsics intrinsics_;
  std::optional<Undistorter> undistorter_;  // set when undistortion applies
  Trajectory ground_truth_;
  std::vector<int> ground_truth_index_;  // per frame, into ground_truth_; -1 when none is near
  std::vector<std::string> warnings_;
  int unassociated_ = 0;
};

}  // namespace vf
