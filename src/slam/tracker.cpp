#include "slam/tracker.h"

#include <algorithm>
#include <cmath>
#include <cstdio>

#include "core/error.h"
#include "fusion/brick_hash.h"

namespace vf::slam {
namespace {

bool samePose(const Pose& a, const Pose& b) {
  const Pose d = a.inverse() * b;
  return d.translation().norm() < 0.01 && Eigen::AngleAxisd(d.linear()).angle() < 0.5 * M_PI / 180.0;
}

}  // namespace

void TrackerParams::validate() const {
  auto require = [](bool ok, const char* what) {
    if (!ok) throw Error(std::string("TrackerParams.") + what);
  };
  require(probation_frames >= 1 && probation_frames <= 100, "probation_frames must be in [1, 100]");
  require(keyframe_novelty >= 0 && keyframe_novelty <= 1, "keyframe_novelty must be in [0, 1]");
  require(keyframe_min_inlier_fraction >= 0 && keyframe_min_inlier_fraction <= 1,
          "keyframe_min_inlier_fraction must be in [0, 1]");
  require(relocalise_by_code >= 0 && relocalise_recent >= 0, "relocalisation candidate counts must be >= 0");
  require(relocalise_min_direction_share >= 0 && relocalise_min_direction_share < 1,
          "relocalise_min_direction_share must be in [0, 1)");
  require(min_depth_share > 0 && min_depth_share < 1, "min_depth_share must be in (0, 1)");
  require(max_speed_m_s > 0 && max_turn_deg_s > 0 && reach_slack_m >= 0 && reach_slack_deg >= 0,
          "the relocalisation reach (speed, turn rate, slack) must be positive");
  require(min_share_of_recent_match >= 0 && min_share_of_recent_match < 1, "min_share_of_recent_match must be in [0, 1)");
  require(recent_frames >= 1 && recent_frames <= 1000, "recent_frames must be in [1, 1000]");
  require(new_map_after_s >= 0, "new_map_after_s must be 0 (never) or more");
  require(retry_reach_m >= 0 && retry_reach_m <= 2, "retry_reach_m must be in [0, 2] m");
  require(dropped_frames_bridged >= 0 && dropped_frames_bridged <= 30, "dropped_frames_bridged must be in [0, 30]");
  require(new_map_min_covered_match >= 0 && new_map_min_covered_match <= 1, "new_map_min_covered_match must be in [0, 1]");
}

Tracker::Tracker(Pipeline& pipeline, PoseSource poses, const TrackerParams& params)
    : pipeline_(pipeline), poses_(poses), params_(params) {
  params_.validate();
}

bool Tracker::hasDepth(const RgbdFrame& frame, std::string* why) const {
  const MeasurementParams& m = pipeline_.params().measurement;
  const DepthImage& depth = frame.depth;
  const size_t n = size_t(depth.width()) * size_t(depth.height());
  size_t in_range = 0;
  for (size_t i = 0; i < n; ++i) {
    const float z = depth.data()[i];
    in_range += z >= m.min_depth_m && z <= m.max_depth_m ? 1 : 0;
  }
  if (double(in_range) >= double(params_.min_depth_share) * double(n)) return true;
  std::vector<float> readings;
  for (size_t i = 0; i < n; ++i)
    if (depth.data()[i] > 0.f && std::isfinite(depth.data()[i])) readings.push_back(depth.data()[i]);
  char text[200];
  if (readings.empty()) {
    std::snprintf(text, sizeof(text), "no valid depth");
  } else {
    std::nth_element(readings.begin(), readings.begin() + long(readings.size() / 2), readings.end());
    std::snprintf(text, sizeof(text),
                  "%.1f%% of the pixels have depth within %.2f-%.1f m (the readings' median is %.2f m)",
                  100.0 * double(in_range) / double(n), m.min_depth_m, m.max_depth_m,
                  double(readings[readings.size() / 2]));
  }
  *why = text;
  return false;
}

Pose Tracker::predictedPose(const RgbdFrame& frame, const std::optional<Pose>& prior_motion) const {
  const Pose& T = pipeline_.pose();
  if (poses_ == PoseSource::GivenIcp && last_given_ && frame.T_world_cam_given)
    return T * (last_given_->inverse() * *frame.T_world_cam_given);
  return pipeline_.params().icp.constant_velocity ? T * prior_motion.value_or(pipeline_.state().last_motion) : T;
}

double Tracker::stepsSinceLastFrame(const RgbdFrame& frame) const {
  // recent_motion_'s last two poses are the pipeline's last motion when the last good frame is
  // the one before this one. Timestamps jitter (consecutive steps of TUM fr1/xyz differ by up to
  // 35 %): only a step at least half as long again as the last, or at most two thirds of it, counts.
  const double last_step_s = recent_motion_.lastStepSeconds();
  if (last_good_index_ != frame.index - 1 || !(last_step_s > 0)) return 1.0;
  const double steps = (frame.timestamp - recent_motion_.lastTime()) / last_step_s;
  return std::isfinite(steps) && steps > 0 && (steps >= 1.5 || steps <= 1.0 / 1.5) ? steps : 1.0;
}

Tracker::Step Tracker::lost(FrameResult result) {
  pipeline_.skip();
  result.tracked = false;
  result.integrated = false;
  result.T_world_cam = pipeline_.pose();
  Step step;
  step.drop_pending = state_ == State::Probation;
  if (state_ != State::Starting) state_ = State::Lost;
  step.result = std::move(result);
  return step;
}

Tracker::Step Tracker::process(const RgbdFrame& frame) {
  if (poses_ != PoseSource::Icp && !frame.T_world_cam_given)
    throw Error("frame " + frame.name + " has no recorded pose, and --poses given or given+icp needs one for every frame");
  pipeline_.measure(frame);
  Step step;
  if (poses_ == PoseSource::Given) step = withGivenPose(frame);
  else if (state_ == State::Starting) step = start(frame);
  else if (state_ == State::Lost) step = relocalise(frame);
  else step = trackOn(frame);
  if (frame.T_world_cam_given) last_given_ = frame.T_world_cam_given;
  return step;
}

Tracker::Step Tracker::withGivenPose(const RgbdFrame& frame) {
  const Pose& T = *frame.T_world_cam_given;
  const double reach_m = double(kBrickCoordLimit) * kBrickSize * double(pipeline_.params().volume.voxel_size_m);
  const double far_m = T.translation().norm() + double(pipeline_.params().measurement.max_depth_m);
  if (!T.matrix().allFinite() || far_m >= reach_m) {
    FrameResult r;
    r.reason = LostReason::OutOfReach;
    char text[200];
    std::snprintf(text, sizeof(text), "its recorded pose lies %.3g m from the origin, beyond the volume's reach of %.3g m",
                  T.translation().norm(), reach_m);
    r.lost_reason = text;
    return lost(r);
  }
  Step step;
  pipeline_.commit(T, true, step.result);
  step.result.pose_given = true;
  state_ = State::Tracking;
  return step;
}

std::optional<Tracker::Step> Tracker::lostWithoutDepth(const RgbdFrame& frame, const char* note) {
  std::string why;
  if (hasDepth(frame, &why)) return std::nullopt;
  FrameResult r;
  r.reason = LostReason::NoDepth;
  r.lost_reason = why + note;
  return lost(r);
}

Tracker::Step Tracker::start(const RgbdFrame& frame) {
  if (std::optional<Step> none = lostWithoutDepth(frame, "; the map starts at the first frame with depth")) return *none;
  Step step;
  const Pose T = poses_ == PoseSource::GivenIcp ? *frame.T_world_cam_given : Pose::Identity();
  pipeline_.commit(T, true, step.result);
  step.result.icp_inlier_fraction = 1.f;
  step.result.map_start = true;
  state_ = State::Tracking;
  markLastGood(T, frame);
  harvest(frame, step.result);
  return step;
}

Tracker::Step Tracker::trackOn(const RgbdFrame& frame) {
  if (std::optional<Step> none = lostWithoutDepth(frame)) return *none;
  TrackingCheck check{pipeline_.pose(), false};
  // Across dropped frames the prior is the recent pace carried over the time unseen, not one
  // frame's step, and the one-frame limits allow for the intervals (dropped_frames_bridged).
  const double steps = stepsSinceLastFrame(frame);
  if (steps != 1.0) {
    check.prior_motion = recent_motion_.lastPose().inverse() * extrapolatedPose(frame.timestamp);
  } else if (last_good_index_ == frame.index - 1 && state_ == State::Tracking) {
    // The pace the last second's good frames walked at, another start where the view leaves a
    // direction free (IcpParams::second_start_at_pace): the last frame's motion may carry an
    // overshoot.
    check.pace_motion = recent_motion_.lastPose().inverse() * extrapolatedPose(frame.timestamp);
  }
  check.limit_intervals = std::clamp(steps, 1.0, 1.0 + double(params_.dropped_frames_bridged));
  FrameResult r = pipeline_.track(predictedPose(frame, check.prior_motion), check);
  if (r.tracked) rejectCollapse(r);
  if (!r.tracked) return lost(r);
  recent_match_.push_back(r.icp_inlier_fraction);
  if (int(recent_match_.size()) > params_.recent_frames) recent_match_.erase(recent_match_.begin());
  if (state_ == State::Tracking) notePriorHeld(frame, r);  // a probation's frames may yet be dropped
  Step step;
  if (state_ == State::Probation) {
    ++probation_count_;
    const bool holds = probation_count_ >= params_.probation_frames;
    pipeline_.commit(r.T_world_cam, holds, r);
    step.pending = !holds;
    step.confirm_pending = holds;
    if (holds) state_ = State::Tracking;
  } else {
    pipeline_.commit(r.T_world_cam, true, r);
  }
  // A relocalised pose anchors the next search only once it has held: one that does not hold
  // was wrong, and the camera is still best looked for from where it was last tracked.
  if (state_ == State::Tracking) markLastGood(r.T_world_cam, frame);
  if (state_ == State::Tracking) harvest(frame, r);
  step.result = std::move(r);
  return step;
}

void Tracker::notePriorHeld(const RgbdFrame& frame, const FrameResult& r) {
  if (r.degenerate_directions <= 0) return;
  if (!prior_held_.empty() && prior_held_.back().last_index >= frame.index - 3) {
    PriorHeldStretch& s = prior_held_.back();
    s.last_index = frame.index;
    s.last_name = frame.name;
    s.directions = std::max(s.directions, r.degenerate_directions);
    return;
  }
  prior_held_.push_back({frame.index, frame.index, frame.name, frame.name, r.degenerate_directions});
}

void Tracker::rejectCollapse(FrameResult& r) const {
  // A few frames first: right after the start or a relocalisation the model is thin and the
  // share is still rising.
  if (int(recent_match_.size()) < std::min(5, params_.recent_frames)) return;
  std::vector<float> sorted = recent_match_;
  std::nth_element(sorted.begin(), sorted.begin() + std::ptrdiff_t(sorted.size() / 2), sorted.end());
  const float median = sorted[sorted.size() / 2];
  if (r.icp_inlier_fraction >= params_.min_share_of_recent_match * median) return;
  r.tracked = false;
  r.reason = LostReason::Collapse;
  char text[200];
  std::snprintf(text, sizeof(text), "%.0f%% of pixels matched the model (residual %.1f mm), where the last %zu frames matched %.0f%% (median)",
                100.f * r.icp_inlier_fraction, 1e3f * r.icp_rmse_m, recent_match_.size(), 100.f * median);
  r.lost_reason = text;
}

Tracker::Step Tracker::relocalise(const RgbdFrame& frame) {
  if (std::optional<Step> none = lostWithoutDepth(frame)) return *none;
  const MeasurementParams& m = pipeline_.params().measurement;
  std::vector<Pose> candidates{recent_motion_.lastPose()};
  auto addCandidate = [&](const Pose& T) {
    for (const Pose& c : candidates)
      if (samePose(c, T)) return;
    candidates.push_back(T);
  };
  if (std::isnan(lost_with_depth_since_)) lost_with_depth_since_ = frame.timestamp;
  // Only the views of the map being tracked: the volume holds no other.
  std::vector<int> ids =
      keyframes_.nearest(encoder_.encode(frame, m.min_depth_m, m.max_depth_m), params_.relocalise_by_code, map_);
  for (int i = std::max(0, keyframes_.size() - params_.relocalise_recent); i < keyframes_.size(); ++i)
    if (keyframes_[i].map == map_ && std::find(ids.begin(), ids.end(), i) == ids.end()) ids.push_back(i);
  const FrameFeatures features = extractFeatures(frame, pipeline_.intrinsics(), m.min_depth_m, m.max_depth_m);
  // Where the frame's features put it relative to a view with a known pose: by 3D-3D alignment,
  // and by perspective-n-point from the view's points (no depth needed at this frame's keypoints).
  auto addFeatureCandidates = [&](const FrameFeatures& view, const Pose& T_world_view) {
    if (features.empty() || view.empty()) return;
    if (const auto relative = estimateRelativePose(features, view)) addCandidate(T_world_view * relative->T_target_source);
    if (const auto relative = estimateRelativePoseFromPixels(features, view, pipeline_.intrinsics()))
      addCandidate(T_world_view * relative->T_target_source);
  };
  if (last_good_frame_) {
    if (!last_good_features_)
      last_good_features_ = extractFeatures(*last_good_frame_, pipeline_.intrinsics(), m.min_depth_m, m.max_depth_m);
    addFeatureCandidates(*last_good_features_, recent_motion_.lastPose());
  }
  for (int id : ids) {
    const Keyframe& k = keyframes_[id];
    addFeatureCandidates(k.features, k.T_world_cam);
    addCandidate(k.T_world_cam);
  }
  // Candidates the camera cannot have reached since it was last tracked are not tried.
  candidates.erase(std::remove_if(candidates.begin(), candidates.end(),
                                  [&](const Pose& c) { return !reachable(c, frame.timestamp); }),
                   candidates.end());
  std::optional<FrameResult> best;
  FrameResult closest;  // the best rejected one, for the report
  for (const Pose& candidate : candidates) {
    pipeline_.predictForTracking(candidate);
    FrameResult r = pipeline_.track(candidate, TrackingCheck{candidate, true});
    if (r.tracked && params_.relocalise_min_direction_share > 0 &&
        r.weakest_direction_share < params_.relocalise_min_direction_share) {
      r.tracked = false;
      r.reason = LostReason::Relocalising;
      char text[200];
      std::snprintf(text, sizeof(text),
                    "the view leaves a direction unmeasured (%.2f%% of the constraint; one wall, a corridor along its "
                    "length): it would align anywhere along it",
                    100.0 * std::max(0.f, r.weakest_direction_share));
      r.lost_reason = text;
    }
    if (r.tracked && (!best || r.icp_inlier_fraction > best->icp_inlier_fraction)) best = r;
    if (!r.tracked && r.icp_inlier_fraction >= closest.icp_inlier_fraction) closest = r;
  }
  if (!best) {
    if (params_.new_map_after_s > 0 && frame.timestamp - lost_with_depth_since_ >= double(params_.new_map_after_s))
      return startNewMap(frame, placeNewMap(frame, features));
    FrameResult r = closest;
    r.reason = LostReason::Relocalising;
    char text[240];
    std::snprintf(text, sizeof(text), "lost; none of %zu candidate poses agrees with the model (best: %s)",
                  candidates.size(), closest.lost_reason.c_str());
    r.lost_reason = text;
    return lost(r);
  }
  ++relocalisations_;
  recent_match_.clear();  // the relocalised view may overlap the model less than the frames before
  Step step;
  state_ = State::Probation;
  probation_count_ = 1;
  const bool holds = probation_count_ >= params_.probation_frames;
  pipeline_.commit(best->T_world_cam, holds, *best);
  step.pending = !holds;
  step.confirm_pending = holds;
  if (holds) {
    state_ = State::Tracking;
    markLastGood(best->T_world_cam, frame);
  }
  step.result = std::move(*best);
  return step;
}

Pose Tracker::extrapolatedPose(double timestamp) const {
  return recent_motion_.extrapolate(timestamp, double(params_.max_speed_m_s));
}

bool Tracker::reachable(const Pose& T, double timestamp) const {
  const double elapsed_s = timestamp - recent_motion_.lastTime();
  if (!std::isfinite(elapsed_s) || elapsed_s <= 0) return true;
  return posesWithin(recent_motion_.lastPose(), T, params_.reach_slack_m + params_.max_speed_m_s * elapsed_s,
                     params_.reach_slack_deg + params_.max_turn_deg_s * elapsed_s);
}

Pose Tracker::placeNewMap(const RgbdFrame& frame, const FrameFeatures& features) {
  const Pose guess = extrapolatedPose(frame.timestamp);
  // The guess, and the guess panned: a walker turning a corner while the camera was lost, or
  // turning back (the ring corridor's gap at walk frame 120: 11 degrees in the 1.1 s since the
  // last good frame, 30 from where the last step's turn carried on).
  std::vector<Pose> starts{guess};
  for (const double pan_deg : {-15.0, 15.0, -30.0, 30.0, -45.0, 45.0}) {
    Pose panned = guess;
    panned.linear() = guess.linear() * Eigen::AngleAxisd(pan_deg * M_PI / 180.0, Eigen::Vector3d::UnitY()).toRotationMatrix();
    starts.push_back(panned);
  }
  if (last_good_features_ && !features.empty()) {
    if (const auto relative = estimateRelativePose(features, *last_good_features_))
      starts.push_back(recent_motion_.lastPose() * relative->T_target_source);
    if (const auto relative = estimateRelativePoseFromPixels(features, *last_good_features_, pipeline_.intrinsics()))
      starts.push_back(recent_motion_.lastPose() * relative->T_target_source);
  }
  // Aligned to the old map where the view overlaps it, the direction the view leaves free held
  // where the start put it: a view along a corridor still measures which way it runs. Judged as
  // a placement (placesNewMap), not as strictly as a relocalisation. A start that does not place
  // it is aligned again with partners further apart (retry_reach_m).
  std::optional<FrameResult> best;
  for (const Pose& start : starts) {
    if (!reachable(start, frame.timestamp)) continue;
    pipeline_.predictForTracking(start);
    FrameResult r = pipeline_.track(start, TrackingCheck{start, true});
    if (!r.tracked && !placesNewMap(r) && params_.retry_reach_m > 0)
      r = pipeline_.track(start, TrackingCheck{start, true, params_.retry_reach_m});
    if (!r.tracked && !placesNewMap(r)) continue;
    if (reachable(r.T_world_cam, frame.timestamp) && (!best || r.icp_inlier_fraction > best->icp_inlier_fraction))
      best = r;
  }
  return best ? best->T_world_cam : guess;
}

bool Tracker::placesNewMap(const FrameResult& r) const {
  const IcpParams& icp = pipeline_.params().icp;
  if (!r.T_world_cam.matrix().allFinite() || r.icp_rmse_m > icp.relocalise_max_rmse_m) return false;
  if (r.icp_model_coverage < icp.relocalise_min_coverage) return false;
  return r.icp_inlier_fraction >= params_.new_map_min_covered_match * r.icp_model_coverage;
}

Tracker::Step Tracker::startNewMap(const RgbdFrame& frame, const Pose& T) {
  pipeline_.startNewMap();
  ++map_;
  Step step;
  step.new_map = true;
  pipeline_.commit(T, true, step.result);
  step.result.icp_inlier_fraction = 1.f;
  step.result.map_start = true;
  state_ = State::Tracking;
  recent_match_.clear();
  markLastGood(T, frame);
  harvest(frame, step.result, true);
  return step;
}

void Tracker::harvest(const RgbdFrame& frame, const FrameResult& result, bool force) {
  if (result.icp_inlier_fraction < params_.keyframe_min_inlier_fraction) return;
  const MeasurementParams& m = pipeline_.params().measurement;
  FrameCode code = encoder_.encode(frame, m.min_depth_m, m.max_depth_m);
  if (code.empty()) return;
  bool moved_on = keyframes_.size() == 0;
  if (!moved_on) {
    const Pose since = keyframes_[keyframes_.size() - 1].T_world_cam.inverse() * result.T_world_cam;
    moved_on = since.translation().norm() > params_.keyframe_distance_m ||
               rotationDeg(since) > params_.keyframe_angle_deg;
  }
  if (!force && !moved_on && !keyframes_.isNewView(code, params_.keyframe_novelty)) return;
  Keyframe k;
  k.frame_index = frame.index;
  k.map = map_;
  k.T_world_cam = result.T_world_cam;
  k.code = std::move(code);
  k.features = extractFeatures(frame, pipeline_.intrinsics(), m.min_depth_m, m.max_depth_m);
  k.cloud = makeKeyframeCloud(frame.depth, pipeline_.intrinsics(), m.min_depth_m, m.max_depth_m);
  keyframes_.add(std::move(k));
}

void Tracker::markLastGood(const Pose& T, const RgbdFrame& frame) {
  recent_motion_.add(T, frame.timestamp, last_good_index_ == frame.index - 1);  // (it checks time goes on)
  lost_with_depth_since_ = std::nan("");
  if (last_good_index_ != frame.index) {
    last_good_frame_.reset();
    last_good_features_.reset();
  }
  last_good_index_ = frame.index;
}

void Tracker::keepLastGoodFrame(RgbdFrame&& frame) {
  if (frame.index != last_good_index_ || last_good_frame_) return;
  last_good_frame_ = std::move(frame);
}

void Tracker::write(std::vector<uint8_t>& out) const {
  ByteWriter w(out);
  w.pod<uint8_t>(uint8_t(state_));
  w.pod<int32_t>(probation_count_);
  w.pod<int32_t>(relocalisations_);
  w.pod<int32_t>(last_good_index_);
  recent_motion_.write(w);
  w.pod(lost_with_depth_since_);
  w.pod<int32_t>(map_);
  w.pod<uint32_t>(uint32_t(recent_match_.size()));
  for (float f : recent_match_) w.pod(f);
  w.pod<uint8_t>(last_given_ ? 1 : 0);
  w.pose(last_given_.value_or(Pose::Identity()));
  w.pod<uint32_t>(uint32_t(prior_held_.size()));
  for (const PriorHeldStretch& h : prior_held_) {
    w.pod<int32_t>(h.first_index);
    w.pod<int32_t>(h.last_index);
    w.pod<int32_t>(h.directions);
    for (const std::string* name : {&h.first_name, &h.last_name}) {
      w.pod<uint32_t>(uint32_t(name->size()));
      w.bytes(name->data(), name->size());
    }
  }
  keyframes_.write(out);
}

void Tracker::read(ByteReader& in) {
  const uint8_t state = in.read<uint8_t>("tracking state");
  if (state > uint8_t(State::Probation)) in.fail("tracking state " + std::to_string(state) + " is unknown");
  state_ = State(state);
  probation_count_ = in.read<int32_t>("probation count");
  relocalisations_ = in.read<int32_t>("relocalisation count");
  if (probation_count_ < 0 || relocalisations_ < 0) in.fail("negative tracking counters");
  last_good_index_ = in.read<int32_t>("last good frame index");
  if (last_good_index_ < -1) in.fail("last good frame index " + std::to_string(last_good_index_));
  recent_motion_.read(in);
  lost_with_depth_since_ = in.read<double>("lost since");
  map_ = in.read<int32_t>("map");
  if (map_ < 0) in.fail("a negative map number");
  const uint32_t recent = in.read<uint32_t>("recent match count");
  if (recent > uint32_t(std::max(params_.recent_frames, 0))) in.fail("recent match count " + std::to_string(recent));
  recent_match_.resize(recent);
  for (float& f : recent_match_) {
    f = in.read<float>("recent match");
    if (!(f >= 0.f && f <= 1.f)) in.fail("a recent match share outside [0, 1]");
  }
  last_good_frame_.reset();
  last_good_features_.reset();
  const bool has_given = in.read<uint8_t>("recorded pose flag") != 0;
  const Pose given = readPose(in, "recorded pose");
  last_given_.reset();
  if (has_given) last_given_ = given;
  const uint32_t stretches = in.read<uint32_t>("prior-held stretch count");
  if (uint64_t(stretches) * 20 > in.remaining()) in.fail("prior-held stretch count " + std::to_string(stretches));
  prior_held_.clear();
  for (uint32_t i = 0; i < stretches; ++i) {
    PriorHeldStretch h;
    h.first_index = in.read<int32_t>("prior-held stretch start");
    h.last_index = in.read<int32_t>("prior-held stretch end");
    h.directions = in.read<int32_t>("prior-held directions");
    if (h.first_index < 0 || h.last_index < h.first_index || h.directions < 1 || h.directions > 6)
      in.fail("a prior-held stretch of frames " + std::to_string(h.first_index) + "-" + std::to_string(h.last_index) +
              " with " + std::to_string(h.directions) + " directions");
    h.first_name = in.readString("prior-held stretch's first frame name");
    h.last_name = in.readString("prior-held stretch's last frame name");
    prior_held_.push_back(std::move(h));
  }
  keyframes_.read(in);
  if (keyframes_.size() > 0 && keyframes_[keyframes_.size() - 1].map > map_)
    in.fail("a keyframe of map " + std::to_string(keyframes_[keyframes_.size() - 1].map) + " beyond the tracker's map " +
            std::to_string(map_));
}

}  // namespace vf::slam
