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

// A sequence of frames (TUM folder, Record3D capture, ...). Loading is random access so that
// worker threads can decode ahead while fusion runs: load() may be called from several threads at
// once (fusion/frame_prefetcher.h), so a source keeps no mutable state that a mutex does not guard.
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
  // How the sensor's depth noise grows with distance, as IcpParams::depth_noise_quadratic (sigma(z)
  // = 1.2 mm + q (z - 0.4 m)^2): ICP weighs readings by it. Empty: a structured-light camera of
  // the Kinect v1 class (TUM, 7-Scenes, ScanNet, Redwood), IcpParams' default; 0: noise that does
  // not grow (rendered depth).
  virtual std::optional<float> depthNoiseQuadratic() const { return std::nullopt; }
  // Gravity's "up" in the frame of the given poses (T_world_cam_given), when the device knows it
  // (ARKit's world is gravity-aligned); empty when not known.
  virtual std::optional<Vec3f> worldUp() const { return std::nullopt; }
};

}  // namespace vf
