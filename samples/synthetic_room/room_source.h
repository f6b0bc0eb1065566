#pragma once
// The synthetic room scan as a FrameSource: tests fuse it in memory, the vdbfuse-synth-room
// command writes it as a TUM folder. Frames are rendered on demand and are a pure function of
// (options, index): load() is thread-safe and order-independent.
#include <cstdint>

#include "core/frame.h"
#include "room_geometry.h"
#include "room_path.h"
#include "room_render.h"

namespace vf::synth {

struct RoomScanOptions {
  int frames = kDefaultFrames;  // frames 0..frames-1 of the 30 Hz path (more than 300 go round again)
  uint64_t seed = 1;            // the sensor noise
  int width = 640, height = 480;  // the Kinect's view at another resolution (tests use small ones)
  SensorModel sensor;
};

class RoomScanSource : public FrameSource {
 public:
  explicit RoomScanSource(RoomScanOptions options = {});

  int size() const override { return options_.frames; }
  // Depth, colour, timestamp and the ground-truth pose (T_world_cam_given) of frame `index`.
  RgbdFrame load(int index) const override;
  Intrinsics depthIntrinsics() const override { return intrinsics_; }
  std::string description() const override;
  Trajectory groundTruth() const override { return path_; }

  const Room& room() const { return room_; }
  const RoomScanOptions& options() const { return options_; }
  // The perfect camera's view of frame `index` (what load() adds the sensor model to).
  CleanView cleanView(int index) const;

 private:
  RoomScanOptions options_;
  Room room_;
  Intrinsics intrinsics_;
  Trajectory path_;
};

}  // namespace vf::synth
