#pragma once
// How much of the sensor's valid depth the fusion range left out. Readings beyond --max-depth-m
// are dropped without a word by the measurement stage; a room larger than the range then has
// holes that look like tracking or sensor faults. The run counts them and says so.
#include <array>
#include <cstdint>
#include <string>

#include "core/frame.h"

namespace vf::app {

class DepthRangeTally {
 public:
  DepthRangeTally(float min_depth_m, float max_depth_m) : min_depth_m_(min_depth_m), max_depth_m_(max_depth_m) {}
  // Counts every other pixel of every other row: a quarter of the work, the same shares.
  void add(const DepthImage& depth);
  int64_t validReadings() const { return valid_; }
  int64_t beyondRange() const { return beyond_; }
  double beyondShare() const { return valid_ > 0 ? double(beyond_) / double(valid_) : 0.0; }
  // The range that would keep `share` of the valid readings, in steps of a quarter metre.
  float rangeKeeping(double share) const;
  // One line for the run's report ("" when under a thousandth was dropped: a few stray far
  // readings are no news); from `suggest_share` on, it names the --max-depth-m that would fuse
  // 99 % of the readings.
  std::string report(double suggest_share = 0.02) const;

 private:
  static constexpr double kNegligibleShare = 0.001;
  static constexpr float kBinM = 0.25f;
  static constexpr int kBins = 200;  // 50 m; readings further away count in the last bin
  float min_depth_m_, max_depth_m_;
  int64_t valid_ = 0, beyond_ = 0;
  std::array<int64_t, kBins> histogram_{};
};

}  // namespace vf::app
