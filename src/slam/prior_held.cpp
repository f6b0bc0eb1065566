#include "slam/prior_held.h"

#include <algorithm>

namespace vf::slam {

int priorHeldFramesBetween(const std::vector<PriorHeldStretch>& stretches, int first_index, int last_index) {
  int frames = 0;
  for (const PriorHeldStretch& s : stretches) {
    const int from = std::max(s.first_index, first_index + 1), to = std::min(s.last_index, last_index);
    frames += std::max(0, to - from + 1);
  }
  return frames;
}

}  // namespace vf::slam
