#include "fusion/reconstruction.h"

#include <algorithm>

#include "core/error.h"
#include "fusion/frame_prefetcher.h"

namespace vf {

Reconstruction::Reconstruction(const FrameSource& source, const ReconstructionOptions& options)
    : source_(source), options_(options) {
  if (options_.max_frames < 0)
    throw Error("ReconstructionOptions.max_frames = " + std::to_string(options_.max_frames) + ": expected 0 (all) or more");
  frame_count_ = options_.max_frames > 0 ? std::min(options_.max_frames, source.size()) : source.size();
  if (frame_count_ == 0) throw Error(source.description() + ": the sequence has no frames");
  pipeline_ = std::make_unique<Pipeline>(options_.params, source.depthIntrinsics(), options_.device,
                                         options_.with_classes);
  if (!options_.dynamic_class_ids.empty()) pipeline_->setDynamicClasses(options_.dynamic_class_ids);
  progress_.settings = options_.settings;
}

void Reconstruction::resume(const std::string& checkpoint_path) {
  RunProgress saved = readCheckpoint(checkpoint_path, *pipeline_, options_.settings);
  if (saved.frames_done > frame_count_)
    throw Error("checkpoint " + checkpoint_path + " is past the end of this run (" +
                std::to_string(saved.frames_done) + " of " + std::to_string(frame_count_) + " frames)");
  progress_ = std::move(saved);
  progress_.settings = options_.settings;
}

void Reconstruction::saveCheckpoint(const std::string& path) { writeCheckpoint(path, *pipeline_, progress_); }

Reconstruction::Outcome Reconstruction::run(const Callbacks& callbacks, bool preload) {
  const int first = progress_.frames_done;
  std::vector<RgbdFrame> preloaded;
  if (preload)
    for (int i = first; i < frame_count_; ++i) preloaded.push_back(source_.load(i));
  FramePrefetcher prefetcher(source_, first, preload ? 0 : frame_count_ - first);
  for (int i = first; i < frame_count_; ++i) {
    RgbdFrame frame = preload ? std::move(preloaded[size_t(i - first)]) : std::move(*prefetcher.next());
    const FrameResult result = pipeline_->processFrame(frame, options_.poses);
    progress_.trajectory.push_back({frame.timestamp, result.T_world_cam});
    if (!result.tracked) progress_.lost.push_back(frame.name + ": " + result.lost_reason);
    progress_.frames_done = i + 1;
    if (callbacks.on_frame) callbacks.on_frame(frame, result);
    if (result.volume_full) return Outcome::VolumeFull;
    if (callbacks.should_stop && callbacks.should_stop()) return i + 1 < frame_count_ ? Outcome::Stopped : Outcome::Finished;
    if (callbacks.checkpoint_every > 0 && callbacks.on_checkpoint && (i + 1) % callbacks.checkpoint_every == 0 &&
        i + 1 < frame_count_)
      callbacks.on_checkpoint();
  }
  return Outcome::Finished;
}

}  // namespace vf
