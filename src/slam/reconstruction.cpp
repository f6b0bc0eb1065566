#include "slam/reconstruction.h"

#include <algorithm>
#include <cstring>

#include "core/byte_reader.h"
#include "core/error.h"
#include "fusion/frame_prefetcher.h"
#include "slam/keyframes.h"

namespace vf {

// A frame on probation: its pose becomes final when the probation ends well.
struct Reconstruction::Pending {
  int index = 0;
  std::string name;
  StampedPose pose;
  int anchor = -1;
};

namespace {

// 64-bit hash of the raw depth: a repeated frame has the same bytes. Eight bytes at a time, so
// that it costs a fraction of a millisecond a frame.
uint64_t depthHash(const DepthImage& depth) {
  const size_t bytes = size_t(depth.width()) * size_t(depth.height()) * sizeof(float);
  const auto* p = reinterpret_cast<const uint8_t*>(depth.data());
  uint64_t h = 0x9E3779B97F4A7C15ull ^ bytes;
  size_t i = 0;
  for (; i + 8 <= bytes; i += 8) {
    uint64_t v;
    std::memcpy(&v, p + i, 8);
    h = (h ^ v) * 0xFF51AFD7ED558CCDull;
    h ^= h >> 32;
  }
  for (; i < bytes; ++i) h = (h ^ p[i]) * 0x100000001B3ull;
  return h;
}

bool anyDepth(const DepthImage& depth) {
  const size_t n = size_t(depth.width()) * size_t(depth.height());
  for (size_t i = 0; i < n; ++i)
    if (depth.data()[i] > 0.f) return true;
  return false;
}

}  // namespace

Reconstruction::Reconstruction(const FrameSource& source, const ReconstructionOptions& options)
    : source_(source), options_(options) {
  if (options_.max_frames < 0)
    throw Error("ReconstructionOptions.max_frames = " + std::to_string(options_.max_frames) + ": expected 0 (all) or more");
  frame_count_ = options_.max_frames > 0 ? std::min(options_.max_frames, source.size()) : source.size();
  if (frame_count_ == 0) throw Error(source.description() + ": the sequence has no frames");
  // Where the camera comes back after the tracking model's window, the old bricks start afresh
  // (IcpParams::restart_stale_bricks) only where the loops can join the two visits and a second
  // pass fuses every frame again: tracked poses, loop closure on.
  PipelineParams first_pass = options_.params;
  first_pass.icp.restart_stale_bricks = options_.poses == PoseSource::Icp && options_.global.loop_closure;
  pipeline_ = std::make_unique<Pipeline>(first_pass, source.depthIntrinsics(), options_.device, options_.with_classes);
  if (!options_.dynamic_class_ids.empty()) pipeline_->setDynamicClasses(options_.dynamic_class_ids);
  // A new map after a long loss is joined to the others, and fused with them, only by the second
  // pass: a run without one keeps searching the map it has.
  slam::TrackerParams tracking = options_.tracking;
  if (options_.poses != PoseSource::Icp || !options_.global.loop_closure) tracking.new_map_after_s = 0;
  tracker_ = std::make_unique<slam::Tracker>(*pipeline_, options_.poses, tracking);
  progress_.settings = options_.settings;
}

Reconstruction::~Reconstruction() = default;

void Reconstruction::resume(const std::string& checkpoint_path) {
  RunProgress saved = readCheckpoint(checkpoint_path, *pipeline_, options_.settings);
  if (saved.frames_done > frame_count_)
    throw Error("checkpoint " + checkpoint_path + " is past the end of this run (" +
                std::to_string(saved.frames_done) + " of " + std::to_string(frame_count_) + " frames)");
  progress_ = std::move(saved);
  progress_.settings = options_.settings;
  restoreSession(progress_.session, checkpoint_path);
}

void Reconstruction::saveCheckpoint(const std::string& path) {
  progress_.session = sessionState();
  writeCheckpoint(path, *pipeline_, progress_);
}

std::vector<uint8_t> Reconstruction::sessionState() const {
  std::vector<uint8_t> out;
  slam::ByteWriter w(out);
  w.pod<int32_t>(pass_);
  w.pod<uint64_t>(last_depth_hash_);
  w.pod<int32_t>(frames_fused_);
  w.pod<uint32_t>(uint32_t(pending_.size()));
  for (const Pending& p : pending_) {
    w.pod<int32_t>(p.index);
    w.pod<uint32_t>(uint32_t(p.name.size()));
    w.bytes(p.name.data(), p.name.size());
    w.pod(p.pose.timestamp);
    w.pose(p.pose.T_world_cam);
    w.pod<int32_t>(p.anchor);
  }
  w.pod<uint32_t>(uint32_t(posed_frames_.size()));
  for (size_t k = 0; k < posed_frames_.size(); ++k) {
    w.pod<int32_t>(posed_frames_[k]);
    w.pod<int32_t>(anchors_[k]);
  }
  w.pod<uint32_t>(uint32_t(odometry_.size()));
  for (const StampedPose& p : odometry_) {
    w.pod(p.timestamp);
    w.pose(p.T_world_cam);
  }
  w.pod(global_);
  tracker_->write(out);
  return out;
}

void Reconstruction::restoreSession(const std::vector<uint8_t>& bytes, const std::string& path) {
  ByteReader in(bytes.data(), bytes.size(), "checkpoint " + path + ": tracking state");
  pass_ = in.read<int32_t>("pass");
  if (pass_ != 1 && pass_ != 2) in.fail("pass " + std::to_string(pass_) + " is neither 1 nor 2");
  for (const LostFrame& l : progress_.lost)
    if (l.index >= (pass_ == 1 ? progress_.frames_done : frame_count_))
      in.fail("a lost frame's index " + std::to_string(l.index) + " is beyond the frames " +
              (pass_ == 1 ? "done" : "of the dataset"));
  last_depth_hash_ = in.read<uint64_t>("depth hash");
  frames_fused_ = in.read<int32_t>("fused frame count");
  const uint32_t pending = in.read<uint32_t>("pending frame count");
  if (pending > in.remaining() / 16) in.fail("pending frame count " + std::to_string(pending) + " exceeds the file");
  pending_.clear();
  for (uint32_t i = 0; i < pending; ++i) {
    Pending p;
    p.index = in.read<int32_t>("pending frame index");
    p.name = in.readString("pending frame name");
    p.pose.timestamp = in.read<double>("pending frame time");
    p.pose.T_world_cam = slam::readPose(in, "pending frame pose");
    p.anchor = in.read<int32_t>("pending frame keyframe");
    pending_.push_back(std::move(p));
  }
  const uint32_t posed = in.read<uint32_t>("posed frame count");
  if (posed != progress_.trajectory.size()) in.fail("posed frame count " + std::to_string(posed) + " differs from the trajectory's");
  posed_frames_.resize(posed);
  anchors_.resize(posed);
  for (uint32_t k = 0; k < posed; ++k) {
    posed_frames_[k] = in.read<int32_t>("posed frame index");
    anchors_[k] = in.read<int32_t>("posed frame keyframe");
    if (posed_frames_[k] < 0 || posed_frames_[k] >= frame_count_) in.fail("a posed frame's index is out of range");
  }
  const uint32_t odometry = in.read<uint32_t>("odometry pose count");
  if (odometry > in.remaining() / 136) in.fail("odometry pose count " + std::to_string(odometry) + " exceeds the file");
  odometry_.resize(odometry);
  for (StampedPose& p : odometry_) {
    p.timestamp = in.read<double>("odometry time");
    p.T_world_cam = slam::readPose(in, "odometry pose");
  }
  global_ = in.read<slam::GlobalReport>("optimisation report");
  tracker_->read(in);
  if (!in.atEnd()) in.fail("trailing bytes");
  // The last well-tracked frame is not in the checkpoint; it is read again from the dataset.
  const int last_good = tracker_->lastGoodFrameIndex();
  if (pass_ == 1 && last_good >= 0) {
    if (last_good >= frame_count_) in.fail("last good frame index " + std::to_string(last_good) + " beyond the dataset");
    RgbdFrame frame = source_.load(last_good);
    frame.index = last_good;
    tracker_->keepLastGoodFrame(std::move(frame));
  }
}

void Reconstruction::loseFrame(int index, const std::string& name, LostReason reason, const std::string& why) {
  progress_.lost.push_back({index, name, reason, why});
}

void Reconstruction::record(const RgbdFrame& frame, const slam::Tracker::Step& step) {
  const int anchor = tracker_->keyframes().size() - 1;
  auto addPose = [&](int index, const StampedPose& pose, int keyframe) {
    progress_.trajectory.push_back(pose);
    posed_frames_.push_back(index);
    anchors_.push_back(keyframe);
  };
  if (step.drop_pending) {
    for (const Pending& p : pending_)
      loseFrame(p.index, p.name, LostReason::Probation,
                "relocalised, but the pose did not hold for the frames after it");
    pending_.clear();
  }
  if (step.confirm_pending) {
    for (const Pending& p : pending_) addPose(p.index, p.pose, p.anchor);
    pending_.clear();
  }
  const FrameResult& r = step.result;
  if (!r.tracked) loseFrame(frame.index, frame.name, r.reason, r.lost_reason);
  else if (step.pending) pending_.push_back({frame.index, frame.name, {frame.timestamp, r.T_world_cam}, anchor});
  else addPose(frame.index, {frame.timestamp, r.T_world_cam}, anchor);
  if (r.integrated && r.bricks_fused > 0) ++frames_fused_;
}

std::optional<Reconstruction::Outcome> Reconstruction::afterFrame(const Callbacks& callbacks, int i,
                                                                  const FrameResult& result) {
  progress_.frames_done = i + 1;
  if (result.volume_full) return Outcome::VolumeFull;
  const bool last = i + 1 == frame_count_ && (pass_ == 2 || !options_.global.loop_closure);
  if (callbacks.should_stop && callbacks.should_stop()) {
    if (i + 1 < frame_count_) return Outcome::Stopped;
    if (last) return Outcome::Finished;
    // The first pass's last frame: the optimisation runs before anything is written.
  }
  if (callbacks.checkpoint_every > 0 && callbacks.on_checkpoint && (i + 1) % callbacks.checkpoint_every == 0 &&
      i + 1 < frame_count_)
    callbacks.on_checkpoint();
  return std::nullopt;
}

namespace {

// The frames first..end-1 in order, each with its index: decoded ahead on worker threads, or all
// decoded before the first is handed out (preload: --bench times fusion without the decoding).
class FrameFeed {
 public:
  FrameFeed(const FrameSource& source, int first, int end, bool preload, int workers)
      : prefetcher_(source, first, preload ? 0 : end - first, FramePrefetcher::kDefaultDepth, workers),
        preload_(preload),
        next_(first) {
    if (preload)
      for (int i = first; i < end; ++i) preloaded_.push_back(source.load(i));
  }
  RgbdFrame next() {
    RgbdFrame frame = preload_ ? std::move(preloaded_[taken_++]) : std::move(*prefetcher_.next());
    frame.index = next_++;
    return frame;
  }

 private:
  FramePrefetcher prefetcher_;
  bool preload_;
  std::vector<RgbdFrame> preloaded_;
  size_t taken_ = 0;
  int next_;
};

}  // namespace

Reconstruction::Outcome Reconstruction::run(const Callbacks& callbacks, bool preload) {
  if (pass_ == 1) {
    const Outcome first = runFirstPass(callbacks, preload);
    if (first != Outcome::Finished) return first;
    if (!optimise()) return Outcome::Finished;
    if (callbacks.on_second_pass) callbacks.on_second_pass(global_);
    if (callbacks.should_stop && callbacks.should_stop()) return Outcome::Stopped;
  }
  return runSecondPass(callbacks, preload);
}

Reconstruction::Outcome Reconstruction::runFirstPass(const Callbacks& callbacks, bool preload) {
  const int first = progress_.frames_done;
  FrameFeed feed(source_, first, frame_count_, preload, FramePrefetcher::workersFor(pipeline_->device()));
  for (int i = first; i < frame_count_; ++i) {
    RgbdFrame frame = feed.next();
    // A recorder that drops frames may repeat the last depth image byte for byte while the camera
    // moves on (7-Scenes: 43 of redkitchen's first 500 frames). Taken at face value it says the
    // camera stood still; it carries no measurement of its own, so it gets no pose and is not fused.
    const uint64_t hash = depthHash(frame.depth);
    const bool repeated = i > 0 && hash == last_depth_hash_ && anyDepth(frame.depth);
    last_depth_hash_ = hash;
    FrameResult result;
    if (repeated) {
      pipeline_->skip();
      result.tracked = false;
      result.reason = LostReason::Repeated;
      result.lost_reason = "the same depth as the frame before";
      result.T_world_cam = pipeline_->pose();
      loseFrame(i, frame.name, result.reason, result.lost_reason);
    } else {
      const slam::Tracker::Step step = tracker_->process(frame);
      record(frame, step);
      result = step.result;
    }
    if (i + 1 == frame_count_) {
      // Frames still on probation at the end have poses that never held for long enough.
      for (const Pending& p : pending_)
        loseFrame(p.index, p.name, LostReason::Probation, "relocalised at the end of the sequence; the pose was not confirmed");
      pending_.clear();
    }
    if (callbacks.on_frame) callbacks.on_frame(frame, result);
    tracker_->keepLastGoodFrame(std::move(frame));  // kept only when its pose is the last good one
    if (const auto outcome = afterFrame(callbacks, i, result)) return *outcome;
  }
  return Outcome::Finished;
}

bool Reconstruction::optimise() {
  if (options_.poses == PoseSource::Given) return false;
  std::vector<Pose> poses;
  for (const StampedPose& p : progress_.trajectory) poses.push_back(p.T_world_cam);
  const std::vector<Pose> moved =
      slam::optimiseTrajectory(tracker_->keyframes(), poses, anchors_, tracker_->priorHeldStretches(),
                                options_.global, &global_);
  // With several maps the first pass's volume holds only the last: all are fused again, joined or
  // not. Where it restarted bricks it came back to, it holds only their later observations.
  global_.bricks_restarted = pipeline_->state().bricks_restarted;
  if (!global_.moved() && tracker_->maps() == 1 && global_.bricks_restarted == 0) return false;
  // The second pass: the first pass's volume is dropped before the new one grows.
  odometry_ = progress_.trajectory;
  for (size_t k = 0; k < moved.size(); ++k) progress_.trajectory[k].T_world_cam = moved[k];
  pass_ = 2;
  progress_.frames_done = 0;
  frames_fused_ = 0;
  first_pass_timer_ = pipeline_->timer();
  pipeline_.reset();
  pipeline_ = std::make_unique<Pipeline>(options_.params, source_.depthIntrinsics(), options_.device,
                                         options_.with_classes);
  if (!options_.dynamic_class_ids.empty()) pipeline_->setDynamicClasses(options_.dynamic_class_ids);
  return true;
}

Reconstruction::Outcome Reconstruction::runSecondPass(const Callbacks& callbacks, bool preload) {
  // The optimised pose of each frame that has one.
  std::vector<int> pose_of(size_t(frame_count_), -1);
  for (size_t k = 0; k < posed_frames_.size(); ++k) pose_of[size_t(posed_frames_[k])] = int(k);
  const int first = progress_.frames_done;
  FrameFeed feed(source_, first, frame_count_, preload, FramePrefetcher::workersFor(pipeline_->device()));
  for (int i = first; i < frame_count_; ++i) {
    RgbdFrame frame = feed.next();
    FrameResult result;
    const int k = pose_of[size_t(i)];
    if (k >= 0) {
      pipeline_->measure(frame);
      pipeline_->fuseAt(progress_.trajectory[size_t(k)].T_world_cam, result);
      if (result.bricks_fused > 0) ++frames_fused_;
    } else {
      pipeline_->skip();
      result.tracked = false;
    }
    if (callbacks.on_frame) callbacks.on_frame(frame, result);
    tracker_->keepLastGoodFrame(std::move(frame));  // kept only when its pose is the last good one
    if (const auto outcome = afterFrame(callbacks, i, result)) return *outcome;
  }
  return Outcome::Finished;
}

}  // namespace vf
