#pragma once
// A folder of per-frame label maps (single-channel PNGs of class ids, e.g. SegFormer output or
// the Record3D person masks), matched to frames by file stem or frame index and brought to the
// depth resolution.
#include <optional>
#include <string>

#include "core/image.h"

namespace vf {

// Nearest-neighbour resampling to width x height for any ratio, pixel-centre aligned: output
// pixel x samples input pixel floor((x + 0.5) * in_width / width). Class ids are never blended.
LabelImage resampleLabelsNearest(const LabelImage& labels, int width, int height);

struct LabelLookup {
  std::optional<LabelImage> labels;  // empty when no file exists for the frame
  std::string path;                  // the file read, or the first path looked for when missing
};

class LabelMapDir {
 public:
  // Throws vf::Error when the folder does not exist.
  explicit LabelMapDir(const std::string& folder);

  // "<stem>.png" when it exists (TUM-style: same stem as the depth/colour file), else
  // "<index>.png" (Record3D masks). Returns the stem path when neither exists.
  std::string pathFor(const std::string& stem, int index) const;

  // Loads the frame's map and resamples it to target_width x target_height when its size
  // differs. Missing file: empty labels plus the path (the caller decides skip or error).
  // Unreadable or colour file: vf::Error naming it. Thread-safe (no mutable state).
  LabelLookup load(const std::string& stem, int index, int target_width, int target_height) const;

  const std::string& folder() const { return folder_; }

 private:
  std::string folder_;
};

}  // namespace vf
