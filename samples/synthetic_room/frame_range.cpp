#include "frame_range.h"

#include <cstdio>

#include "core/error.h"

namespace vf::synth {

FrameRange parseFrameRange(const std::string& text, const std::string& option) {
  int from = -1, count = 0, consumed = 0;
  if (std::sscanf(text.c_str(), "%d:%d%n", &from, &count, &consumed) != 2 || consumed != int(text.size()) || from < 0 ||
      count < 1)
    throw Error(option + " '" + text + "': expected FROM:COUNT, two integers with FROM >= 0 and COUNT >= 1 (e.g. 300:60)");
  return {from, count};
}

void checkWithin(const FrameRange& range, int frames, const std::string& option) {
  if (range.end() > frames)
    throw Error(option + " " + toString(range) + ": reaches frame " + std::to_string(range.end() - 1) +
                ", but the walk has frames 0.." + std::to_string(frames - 1) + " (--frames " + std::to_string(frames) + ")");
}

void checkDisjoint(const std::vector<std::pair<std::string, FrameRange>>& ranges) {
  for (size_t i = 0; i < ranges.size(); ++i)
    for (size_t j = i + 1; j < ranges.size(); ++j) {
      const FrameRange &a = ranges[i].second, &b = ranges[j].second;
      if (a.from < b.end() && b.from < a.end())
        throw Error(ranges[i].first + " " + toString(a) + " and " + ranges[j].first + " " + toString(b) +
                    " share frames; give runs that do not overlap");
    }
}

std::string toString(const FrameRange& range) { return std::to_string(range.from) + ":" + std::to_string(range.count); }

}  // namespace vf::synth
