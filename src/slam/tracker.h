#pragma once
// Decides, frame by frame, which pose to trust and whether to fuse, driving the fusion Pipeline
// step by step (fusion/pipeline.h: measure, track, commit or skip):
//   Starting   until a frame has depth: the map starts there (a lens cap, a warming sensor).
//   Tracking   frame-to-model ICP from the predicted pose; a frame the judge rejects (or one that
//              matched far less than the frames before it) is not fused, has no pose, and
//              tracking is lost.
//   Lost       each frame tries candidate poses: the last good one, and the keyframes nearest by
//              appearance code, also moved by the point features they (and the last good frame)
//              share with the frame; ICP from each against the model raycast from there, judged
//              strictly; a view that leaves a direction unmeasured is not taken.
//   Probation  a relocalised pose must track for a few frames before fusion resumes; their poses
//              are pending until then, and dropped if the pose does not hold.
// Keyframes are harvested while tracking is good and the view is new (slam/keyframes.h).
#include <optional>
#include <string>
#include <vector>

#include "core/frame.h"
#include "fusion/pipeline.h"
#include "slam/frame_features.h"
#include "slam/keyframes.h"
#include "slam/prior_held.h"

namespace vf::slam {

struct TrackerParams {
  int probation_frames = 5;                // frames a relocalised pose must hold before fusion resumes
  float keyframe_novelty = 0.3f;           // a new keyframe's code differs this much from every stored one,
  float keyframe_distance_m = 0.3f;        // or the camera moved this far from the last keyframe,
  float keyframe_angle_deg = 20.f;         // or turned this much
  float keyframe_min_inlier_fraction = 0.5f;  // only views tracked at least this well become keyframes
  int relocalise_by_code = 3;              // keyframes nearest by code tried as relocalisation candidates
  int relocalise_recent = 2;               // and the latest keyframes, whatever their code
  float min_depth_share = 0.02f;           // less of the image in range counts as no depth
  // A camera that jumped (frames cut out, a dropped stretch) can leave ICP in a wrong minimum
  // within the jump limits: fr1/xyz with frames 320-379 cut, the frame after the cut matched 22 %
  // of its pixels (residual 18.7 mm) where the frames before matched 78-86 % (4.5-8.6 mm), and
  // was fused 75 cm from where it was taken. A frame matching less than this share of the median
  // of the last `recent_frames` tracked frames is treated as lost, and relocalised.
  float min_share_of_recent_match = 0.5f;
  int recent_frames = 15;
  // A relocalised pose must be one the camera could have reached since it was last tracked: a
  // hand-held or walking camera moves at most this fast (plus the slack below), so a view that
  // merely looks like an earlier one (a corridor's twin doors) is not taken for it.
  float max_speed_m_s = 2.f;
  float max_turn_deg_s = 180.f;
  float reach_slack_m = 0.3f;
  float reach_slack_deg = 30.f;
  // A relocalised pose must be pinned down by the geometry in every direction: a view of a
  // corridor along its length, or of one wall, aligns as well anywhere along it (the tracker
  // leaves such a direction to the motion prior, which a lost camera does not have). The weakest
  // direction's share of the point-to-plane constraint, beyond the model normals' own scatter
  // (FrameResult::weakest_direction_share), must reach this. Measured at the relocalised poses:
  // the ring corridor's wrong ones -0.0024 to -0.0015 (2.4 to 3.4 m off; with 30 frames left out
  // at frame 400 of 520 the run's ATE was 100.7 cm, refused 2.1 cm, and the rest of that leg
  // stays lost); 7-Scenes kitchen's right ones after 60 blank frames 0.0048 to 0.0061.
  float relocalise_min_direction_share = 0.0025f;  // 0: any view
  void validate() const;
};

class Tracker {
 public:
  Tracker(Pipeline& pipeline, PoseSource poses, const TrackerParams& params = {});

  enum class State : uint8_t { Starting, Tracking, Lost, Probation };
  // What became of one frame.
  struct Step {
    FrameResult result;        // tracked = it has a pose (final or pending); integrated = fused
    bool pending = false;      // its pose waits for the probation to end
    bool confirm_pending = false;  // the probation ended well: every pending pose is final now
    bool drop_pending = false;     // the probation failed: the pending frames are lost
  };
  Step process(const RgbdFrame& frame);

  State state() const { return state_; }
  const KeyframeStore& keyframes() const { return keyframes_; }
  KeyframeStore& keyframes() { return keyframes_; }
  int relocalisations() const { return relocalisations_; }
  // In frame order; a frame or two measured in full between two such frames does not split one.
  const std::vector<PriorHeldStretch>& priorHeldStretches() const { return prior_held_; }
  // The frame whose pose is the last good one: after a gap the camera is most often still near
  // where it was last seen, so its features are the first a lost frame is matched against. The
  // session hands it over after each step (no copy); -1 / false when none is kept.
  int lastGoodFrameIndex() const { return last_good_index_; }
  void keepLastGoodFrame(RgbdFrame&& frame);

  // For checkpoints (the pipeline saves its own state).
  void write(std::vector<uint8_t>& out) const;
  void read(ByteReader& in);

 private:
  Step start(const RgbdFrame& frame);
  Step trackOn(const RgbdFrame& frame);
  Step relocalise(const RgbdFrame& frame);
  Step lost(FrameResult result);
  Step withGivenPose(const RgbdFrame& frame);
  // The share of the frame's pixels with depth in range, and the median of all its readings.
  bool hasDepth(const RgbdFrame& frame, std::string* why) const;
  // The frame lost for want of depth (the report ends with `note`); nullopt when it has depth.
  std::optional<Step> lostWithoutDepth(const RgbdFrame& frame, const char* note = "");
  void harvest(const RgbdFrame& frame, const FrameResult& result);
  Pose predictedPose(const RgbdFrame& frame) const;
  void markLastGood(const Pose& T, const RgbdFrame& frame);
  // Marks a tracked result lost when it matched far less than the recent frames.
  void rejectCollapse(FrameResult& r) const;
  void notePriorHeld(const RgbdFrame& frame, const FrameResult& r);

  Pipeline& pipeline_;
  PoseSource poses_;
  TrackerParams params_;
  FernEncoder encoder_;
  KeyframeStore keyframes_;
  State state_ = State::Starting;
  int probation_count_ = 0;
  int relocalisations_ = 0;
  Pose last_good_ = Pose::Identity();          // the last pose tracked well (a relocalised one once it held)
  double last_good_time_ = 0;                  // its frame's timestamp
  int last_good_index_ = -1;                   // its frame's index
  std::vector<float> recent_match_;            // inlier fractions of the last tracked frames, oldest first
  std::optional<RgbdFrame> last_good_frame_;   // that frame, once handed over
  std::optional<FrameFeatures> last_good_features_;  // its features, computed when first needed
  std::optional<Pose> last_given_;             // GivenIcp: the recorded pose of the previous frame
  std::vector<PriorHeldStretch> prior_held_;
};

}  // namespace vf::slam
