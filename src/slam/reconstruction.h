#pragma once
// A whole reconstruction run as a library object, in up to two passes over a FrameSource
// (decoding ahead on a worker thread):
//   1. tracking and fusion: the Tracker decides each frame's pose (slam/tracker.h);
//   then the keyframes' loops are closed and the poses optimised (slam/global_optimisation.h);
//   2. where that moved them, or where tracking started new maps after long losses (the first
//      pass's volume then holds only the last): a fresh volume, every posed frame fused again at
//      its new pose.
// It keeps the trajectory of the frames that have a pose, the report of those that have none,
// and checkpoints in either pass (fusion/checkpoint.h). The caller (the reconstruct command, a
// test) chooses the outputs and reacts to progress through callbacks; nothing here prints.
#include <functional>
#include <memory>
#include <optional>
#include <string>
#include <vector>

#include "core/frame.h"
#include "fusion/checkpoint.h"
#include "fusion/pipeline.h"
#include "slam/global_optimisation.h"
#include "slam/tracker.h"

namespace vf {

struct ReconstructionOptions {
  PipelineParams params;
  slam::TrackerParams tracking;
  // Loops closed and the poses optimised after the first pass; where that moved them, a second
  // pass fuses every frame again at its optimised pose. Not with --poses given (ARKit's and
  // motion capture's are consistent already).
  slam::GlobalParams global;
  Device device = Device::Auto;
  PoseSource poses = PoseSource::Icp;
  bool with_classes = false;
  std::vector<int> dynamic_class_ids;  // kept out of geometry and tracking (still voted)
  int max_frames = 0;                  // 0 = every frame of the source
  RunSettings settings;                // what a checkpoint must match to be resumed
};

class Reconstruction {
 public:
  Reconstruction(const FrameSource& source, const ReconstructionOptions& options);
  ~Reconstruction();

  // Why run() returned.
  enum class Outcome {
    Finished,    // every frame was processed
    Stopped,     // should_stop() asked for it
    VolumeFull,  // memory for bricks ran out on the last frame processed (it is kept)
  };
  struct Callbacks {
    // After each frame: the frame (still decoded) and what fusion made of it.
    std::function<void(const RgbdFrame& frame, const FrameResult& result)> on_frame;
    // When the second pass starts (after the optimisation), with what the optimisation found.
    std::function<void(const slam::GlobalReport& report)> on_second_pass;
    // Polled after each frame; true stops the run there.
    std::function<bool()> should_stop;
    // Every checkpoint_every frames (except after the last): the caller writes its outputs and,
    // usually, saveCheckpoint().
    int checkpoint_every = 0;
    std::function<void()> on_checkpoint;
  };
  // Processes the frames from framesDone() on. preload: decode them all before the first one is
  // fused (benchmarks time fusion alone); otherwise a worker thread decodes a few frames ahead.
  Outcome run(const Callbacks& callbacks, bool preload = false);

  // Continues a stopped run: restores the pipeline and the progress from the checkpoint, which
  // must have been written with the same settings (vf::Error naming the path otherwise).
  void resume(const std::string& checkpoint_path);
  void saveCheckpoint(const std::string& path);

  int frameCount() const { return frame_count_; }  // frames this run fuses in all
  int framesDone() const { return progress_.frames_done; }  // in the current pass
  int pass() const { return pass_; }
  // The first pass's poses (what tracking alone said), and what the optimisation did.
  const Trajectory& odometry() const { return odometry_; }
  const slam::GlobalReport& globalReport() const { return global_; }
  // The first pass's stage times, kept when the second pass replaces its pipeline.
  const StageTimer& firstPassTimer() const { return first_pass_timer_; }
  // The poses of the frames that have one (a frame relocalised and still on probation has none
  // yet), and the frames that have none, with why.
  const Trajectory& trajectory() const { return progress_.trajectory; }
  const std::vector<LostFrame>& lostFrames() const { return progress_.lost; }
  int framesFused() const { return frames_fused_; }
  const slam::Tracker& tracker() const { return *tracker_; }
  Pipeline& pipeline() { return *pipeline_; }
  const Pipeline& pipeline() const { return *pipeline_; }

 private:
  struct Pending;
  Outcome runFirstPass(const Callbacks& callbacks, bool preload);
  Outcome runSecondPass(const Callbacks& callbacks, bool preload);
  // After the first pass: loops, the pose graph, and the trajectory moved; true when it moved.
  bool optimise();
  // Stop, volume full or checkpoint after frame i of the current pass; nullopt to go on.
  std::optional<Outcome> afterFrame(const Callbacks& callbacks, int i, const FrameResult& result);
  void record(const RgbdFrame& frame, const slam::Tracker::Step& step);
  void loseFrame(int index, const std::string& name, LostReason reason, const std::string& why);
  std::vector<uint8_t> sessionState() const;
  void restoreSession(const std::vector<uint8_t>& bytes, const std::string& path);

  const FrameSource& source_;
  ReconstructionOptions options_;
  int frame_count_ = 0;
  std::unique_ptr<Pipeline> pipeline_;
  std::unique_ptr<slam::Tracker> tracker_;
  RunProgress progress_;
  std::vector<Pending> pending_;      // frames on probation: posed, not yet final
  uint64_t last_depth_hash_ = 0;      // the previous frame's raw depth, to recognise a repeat
  int frames_fused_ = 0;
  // Per trajectory entry: its frame's index, and the keyframe it was tracked after (-1: none yet).
  std::vector<int> posed_frames_, anchors_;
  int pass_ = 1;
  Trajectory odometry_;               // the first pass's trajectory, once the second pass starts
  StageTimer first_pass_timer_;
  slam::GlobalReport global_;
};

}  // namespace vf
