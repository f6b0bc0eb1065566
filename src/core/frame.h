#pragma once
#include <memory>
#include <optional>
#include <string>

#include "core/image.h"
#include "core/intrinsics.h"
#include "core/pose.h"

namespace vf {

// One RGB-D observation as the readers deliver it: depth in metres registered to the depth
// camera, color at the depth resolution, optional per-pixel class ids and a pose from the source.
struct RgbdFrame {
  int index = 0;
  double timestamp = 0;
  DepthImage depth;
  ColorImage color;                         // empty when the source has no color
  LabelImage labels;                        // empty when no label map was given
  std::optional<Pose> T_world_cam_given;    // pose recorded by the device (phones) or mocap
  std::string name;                         // file stem, used to match label maps
};

// A sequence of frames (TUM folder, Record3D capture, ...). Loading is random access so that a
// worker thread can decode ahead while fusion runs.
class FrameSource {
 public:
  virtual ~FrameSource() = default;
  virtual int size() const = 0;
  virtual RgbdFrame load(int index) const = 0;  // throws vf::Error naming the file on failure
  virtual Intrinsics depthIntrinsics() const = 0;
  virtual Distortion depthDistortion() const { return {}; }
  virtual std::string description() const = 0;
  // Ground-truth trajectory if the source has one (TUM groundtruth.txt), else empty.
  virtual Trajectory groundTruth() const { return {}; }
  // False when colour pixel (u, v) does not see what depth pixel (u, v) sees (ScanNet: colour from
  // another camera, resampled to the depth size), so that colour terms that assume it
  // (photometric tracking) should be left out.
  virtual bool colorRegisteredToDepth() const { return true; }
};

}  // namespace vf
