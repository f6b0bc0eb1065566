#pragma once
// A run of frames of a synthetic walk, FROM..FROM+COUNT-1 (path indices, 0-based), named on the
// command line as "FROM:COUNT": frames left out (--gap), blanked (--blank) or seen up close
// against one wall (--close-wall).
#include <string>
#include <vector>

namespace vf::synth {

struct FrameRange {
  int from = 0, count = 0;
  int end() const { return from + count; }  // one past the last
  bool contains(int index) const { return index >= from && index < end(); }
};

// "120:30" -> {120, 30}. Throws vf::Error naming `option` and the text when it is not two
// integers FROM >= 0 and COUNT >= 1 joined by ':'.
FrameRange parseFrameRange(const std::string& text, const std::string& option);

// Throws vf::Error naming `option` when a range reaches past the walk's `frames`.
void checkWithin(const FrameRange& range, int frames, const std::string& option);

// Throws vf::Error naming both options when two ranges share a frame (a frame is either left
// out or blanked, not both; two overlapping gaps are most likely a typo).
void checkDisjoint(const std::vector<std::pair<std::string, FrameRange>>& ranges);

std::string toString(const FrameRange& range);  // "FROM:COUNT"

}  // namespace vf::synth
