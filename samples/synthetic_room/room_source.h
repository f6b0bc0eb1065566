#pragma once
// The synthetic scans as a FrameSource: tests fuse them in memory, the vdbfuse-synth-room
// command writes them as TUM folders. Two scenes: the room (room_geometry.h, the default) and
// the ring corridor (corridor_geometry.h). Frames are rendered on demand and are a pure function
// of (options, index): load() is thread-safe and order-independent.
//
// Stress variants (for tracking): gaps leave frames out of the sequence (the camera jumps; the
// timestamps of the frames kept are those of the walk, so the gap shows in them too), blanks
// keep the frames with all-zero depth and black colour (a covered lens), and a close-wall run
// turns the corridor's camera to one plain wall up close (corridor_path.h).
#include <cstdint>
#include <optional>
#include <string>
#include <vector>

#include "core/frame.h"
#include "frame_range.h"
#include "room_geometry.h"
#include "room_path.h"
#include "room_render.h"

namespace vf::synth {

enum class Scene { kRoom, kCorridor };
Scene parseScene(const std::string& name);  // room | corridor; throws vf::Error otherwise
std::string sceneName(Scene scene);

struct RoomScanOptions {
  Scene scene = Scene::kRoom;
  int frames = kDefaultFrames;  // frames 0..frames-1 of the 30 Hz walk (the room's: more than 300 go round again)
  uint64_t seed = 1;            // the sensor noise
  int width = 640, height = 480;  // the Kinect's view at another resolution (tests use small ones)
  SensorModel sensor;
  std::vector<FrameRange> gaps;    // walk frames left out of the sequence
  std::vector<FrameRange> blanks;  // walk frames written with no depth and black colour
  std::optional<FrameRange> close_wall;  // corridor only
  uint64_t walk = 0;                     // corridor only: 0 the default walk, others vary it (corridor_path.h)
};
// A scene's defaults: the room's 300 frames with its sensor; the corridor's 1200 frames (38 m)
// with kinectV1Sensor().
RoomScanOptions scanDefaults(Scene scene);

class RoomScanSource : public FrameSource {
 public:
  // Throws vf::Error naming the option when a size, a frame count or a run is out of range.
  explicit RoomScanSource(RoomScanOptions options = {});

  int size() const override { return int(written_.size()); }  // the frames written: the walk less its gaps
  // Depth, colour, timestamp and the ground-truth pose (T_world_cam_given) of frame `index` of
  // the sequence (the walk's frame walkIndex(index)).
  RgbdFrame load(int index) const override;
  Intrinsics depthIntrinsics() const override { return intrinsics_; }
  std::string description() const override;
  Trajectory groundTruth() const override;  // one pose per frame of the sequence

  const Room& room() const { return room_; }
  const RoomScanOptions& options() const { return options_; }
  // The perfect camera's view of frame `index` of the sequence (what load() adds the sensor to).
  CleanView cleanView(int index) const;

  int walkIndex(int index) const { return written_.at(size_t(index)); }
  bool blank(int walk_index) const;
  const Trajectory& walk() const { return walk_; }  // every frame of the walk, gaps included
  // The poses of the frames that carry depth (neither left out nor blanked): what saw the scene.
  Trajectory depthPoses() const;

 private:
  RoomScanOptions options_;
  Room room_;
  Intrinsics intrinsics_;
  Trajectory walk_;
  std::vector<int> written_;  // walk index of each frame of the sequence
};

}  // namespace vf::synth
