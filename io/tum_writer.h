#pragma once
// Writes any FrameSource as a TUM RGB-D folder, so captures from other devices can be read by TUM
// tools (and by vf::TumDataset):
//   depth/<ts>.png   16-bit, value = round(depth_m * 5000), 0 = no reading
//   rgb/<ts>.png     8-bit colour at the depth resolution (registered to depth)
//   rgb.txt, depth.txt           "timestamp path" lists
//   groundtruth.txt              "timestamp tx ty tz qx qy qz qw" from the source's poses
//   camera_intrinsics.txt        "fx fy cx cy" and "k1 k2 p1 p2 k3" lines after comments
// <ts> is the frame timestamp with 6 decimals, as in the TUM sequences.
#include <functional>
#include <string>

#include "core/frame.h"

namespace vf {

struct TumWriteOptions {
  int max_frames = -1;  // < 0: all frames
  // Called after each frame is written with (frames done, frames total); may be called from
  // worker threads, one call at a time.
  std::function<void(int, int)> progress;
};

struct TumWriteResult {
  int frames = 0;
  int poses = 0;  // lines written to groundtruth.txt
};

// Writes into a temporary folder beside `folder` and renames it into place when every file is
// written, replacing an existing `folder` as a whole (the caller decides whether that is allowed).
// Throws vf::Error naming the folder or file when anything cannot be read or written; the old
// folder then stays as it was. Frames are loaded and written in parallel.
TumWriteResult writeTumFolder(const FrameSource& source, const std::string& folder,
                              const TumWriteOptions& options = {});

// "1305031102.175304": the file stem and list timestamp used for a frame.
std::string tumTimestampString(double timestamp_s);

}  // namespace vf
