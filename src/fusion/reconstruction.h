#pragma once
// A whole reconstruction run as a library object: the Pipeline, the frame loop over a
// FrameSource (decoding ahead on a worker thread), the trajectory, the lost-frame reports and
// checkpoints (fusion/checkpoint.h). The caller (the reconstruct command, a test) chooses the
// outputs and reacts to progress through callbacks; nothing here prints.
#include <functional>
#include <memory>
#include <string>
#include <vector>

#include "core/frame.h"
#include "fusion/checkpoint.h"
#include "fusion/pipeline.h"

namespace vf {

struct ReconstructionOptions {
  PipelineParams params;
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

  // Why run() returned.
  enum class Outcome {
    Finished,    // every frame was processed
    Stopped,     // should_stop() asked for it
    VolumeFull,  // memory for bricks ran out on the last frame processed (it is kept)
  };
  struct Callbacks {
    // After each frame: the frame (still decoded) and what fusion made of it.
    std::function<void(const RgbdFrame& frame, const FrameResult& result)> on_frame;
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
  int framesDone() const { return progress_.frames_done; }
  const Trajectory& trajectory() const { return progress_.trajectory; }
  const std::vector<std::string>& lostFrames() const { return progress_.lost; }
  Pipeline& pipeline() { return *pipeline_; }
  const Pipeline& pipeline() const { return *pipeline_; }

 private:
  const FrameSource& source_;
  ReconstructionOptions options_;
  int frame_count_ = 0;
  std::unique_ptr<Pipeline> pipeline_;
  RunProgress progress_;
};

}  // namespace vf
