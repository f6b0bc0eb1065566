#pragma once
// A FrameSource over a list of image files: what 7-Scenes/3DMatch, Replica, ScanNet and Redwood
// folders become once their layout is read (io/dataset_layouts.h). Depth is a 16-bit PNG in
// `depth_units_per_metre`, colour any PNG/JPG; poses and timestamps come with the list.
#include <optional>
#include <string>
#include <vector>

#include "core/frame.h"

namespace vf {

struct FrameFiles {
  std::string depth;                    // 16-bit PNG path
  std::string color;                    // PNG/JPG path, empty when there is none
  std::optional<Pose> T_world_cam;      // camera-to-world from the dataset, when it has one
  double timestamp = 0;                 // seconds
  std::string name;                     // file stem, matches label maps
};

struct FrameList {
  std::string folder;
  std::string layout;                   // "7-Scenes/3DMatch", "Replica", ... (for messages)
  std::vector<FrameFiles> frames;
  float fx = 0, fy = 0, cx = 0, cy = 0; // depth camera
  std::string intrinsics_source;
  int expected_width = 0, expected_height = 0;  // 0 = take the first depth image's size
  float depth_units_per_metre = 1000;
  std::string depth_scale_source;
  uint16_t depth_invalid_value = 0;     // a second "no reading" value besides 0 (7-Scenes: 65535)
  bool color_registered = true;         // colour pixel (u, v) sees what depth pixel (u, v) sees
  std::optional<float> depth_noise_quadratic;  // FrameSource::depthNoiseQuadratic()
  bool resize_color = false;            // colour at another size (same aspect ratio within 1 %) is
                                        // area-resized to the depth size
};

class FrameListSource : public FrameSource {
 public:
  // Checks that every listed file is there (a dangling link is an error, not a frame without
  // colour), reads the first depth image for the size and checks the camera against it; throws
  // vf::Error naming the file when one is missing, the size does not match expected_width x
  // expected_height, or the intrinsics cannot be fused (naming intrinsics_source).
  explicit FrameListSource(FrameList list);

  int size() const override { return int(list_.frames.size()); }
  RgbdFrame load(int index) const override;  // thread-safe
  Intrinsics depthIntrinsics() const override { return intrinsics_; }
  std::string description() const override;
  // The dataset's poses, with the frames' timestamps (frames without one are left out).
  Trajectory groundTruth() const override;
  bool colorRegisteredToDepth() const override { return list_.color_registered; }
  std::optional<float> depthNoiseQuadratic() const override { return list_.depth_noise_quadratic; }

  const FrameList& list() const { return list_; }

 private:
  FrameList list_;
  Intrinsics intrinsics_;
};

// The first of `candidates` (paths) that is there as a folder entry, a dangling link included: the
// readers list it, and FrameListSource then refuses it by name instead of fusing the frame
// without colour. "" when none is there.
std::string presentFile(const std::vector<std::string>& candidates);

// 16-bit PNG -> metres: raw / units_per_metre, with 0 and `invalid_value` (when non-zero)
// meaning no reading.
DepthImage readScaledDepthPng(const std::string& path, float units_per_metre, uint16_t invalid_value);

// Whether width / height of two images differ by more than 1 %: resizing one onto the other would
// stretch it. ScanNet's 1296x968 colour over its 640x480 depth differs by 0.4 %.
bool aspectRatiosDiffer(int w1, int h1, int w2, int h2);

// Box-filters `color` to width x height (each output pixel the mean of the input it covers).
ColorImage resizeColorArea(const ColorImage& color, int width, int height);

}  // namespace vf
