#include "app/depth_range_tally.h"

#include <algorithm>
#include <cmath>
#include <cstdio>

namespace vf::app {

void DepthRangeTally::add(const DepthImage& depth) {
  for (int y = 0; y < depth.height(); y += 2) {
    const float* row = &depth(0, y);
    for (int x = 0; x < depth.width(); x += 2) {
      const float d = row[x];
      if (!std::isfinite(d) || d < min_depth_m_) continue;  // no reading, or too near to be one
      ++valid_;
      beyond_ += d > max_depth_m_ ? 1 : 0;
      ++histogram_[size_t(std::min(kBins - 1, int(d / kBinM)))];
    }
  }
}

float DepthRangeTally::rangeKeeping(double share) const {
  const double wanted = share * double(valid_);
  int64_t kept = 0;
  for (int bin = 0; bin < kBins; ++bin) {
    kept += histogram_[size_t(bin)];
    if (double(kept) >= wanted) return float(bin + 1) * kBinM;
  }
  return float(kBins) * kBinM;
}

std::string DepthRangeTally::report(double suggest_share) const {
  if (beyondShare() < kNegligibleShare) return "";
  char line[256];
  std::snprintf(line, sizeof line, "depth: %.1f %% of the valid readings lie beyond --max-depth-m %.1f m and were not fused",
                100.0 * beyondShare(), max_depth_m_);
  std::string text = line;
  if (beyondShare() >= suggest_share) {
    std::snprintf(line, sizeof line, "; --max-depth-m %.1f would fuse 99 %% of them (farther readings are noisier)",
                  std::max(rangeKeeping(0.99), max_depth_m_));
    text += line;
  }
  return text;
}

}  // namespace vf::app
