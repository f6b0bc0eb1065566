#pragma once
// The KinectFusion loop: measure -> track -> integrate -> raycast, per frame, on one backend.
// Owns the sparse volume and every per-frame buffer (frame buffers are allocated once in the
// constructor; the volume grows with the scene).
#include <memory>
#include <optional>
#include <string>
#include <vector>

#include "core/brick_volume.h"
#include "core/frame.h"
#include "fusion/device.h"
#include "fusion/lost_reason.h"
#include "fusion/params.h"
#include "fusion/stage_timer.h"

namespace vf {

class SparseVolume;

// How the camera pose of each frame is obtained.
enum class PoseSource {
  Icp,       // frame-to-model ICP (KinectFusion); the world frame is the first camera's
  Given,     // trust the frame's recorded pose (phones, mocap); the world is the recording's
  GivenIcp,  // start ICP from the recorded relative motion and refine; the recording's world
};


struct FrameResult {
  bool tracked = true;      // false: pose rejected, last good pose kept, frame not integrated
  bool map_start = false;   // the first frame of a map: placed (at the origin, a given pose, or where the walk led), not tracked
  bool pose_given = false;  // fused at its recorded pose (--poses given): nothing was matched
  LostReason reason = LostReason::None;
  bool integrated = false;
  bool volume_full = false; // memory ran out: some of this frame's bricks could not be allocated
  int bricks_fused = 0;     // bricks the frame's depth reached (integrate and raycast cost follows it)
  int bricks_restarted = 0; // of those, bricks it came back to and restarted (IcpParams::restart_stale_bricks)
  Pose T_world_cam = Pose::Identity();
  int icp_inliers = 0;
  float icp_inlier_fraction = 0.f;
  float icp_model_coverage = 0.f;  // share of the measured pixels that land on the model's surface
  float icp_rmse_m = 0.f;
  std::string lost_reason;  // why tracking was rejected
  // Directions of the pose the view left unconstrained (one wall: three), held by the motion
  // prior; and how far the solution moved from the predicted pose.
  int degenerate_directions = 0;
  // The weakest direction's share of the point-to-plane constraint beyond the model normals'
  // own scatter (1: not measured): about 0 for a corridor along its length.
  float weakest_direction_share = 1.f;
  float jump_m = 0.f, jump_deg = 0.f;
  // > 0: the pose came from a second solve, started at the motion prior or at the camera's pace,
  // which fitted the frame better than the first (IcpParams::second_start_at_prior,
  // second_start_at_pace); how far apart the two lay.
  float second_start_moved_m = 0.f;
  // That start was the walker's median pace (IcpParams::second_start_at_pace), not the last
  // frame's motion carried on.
  bool second_start_at_pace = false;
};

// What a track() result is judged against: the pose the camera was at (the one-frame motion
// limits apply from it) and whether the predicted pose was a motion prediction (the jump limit
// applies) or a relocalisation candidate (neither applies; stricter agreement does).
struct TrackingCheck {
  Pose T_world_previous = Pose::Identity();
  bool relocalising = false;
  // > 0: the coarsest pyramid level pairs points up to this far apart, the middle one half-way
  // down to IcpParams::max_distance_m, the finest that (a start tens of centimetres off, which
  // the usual reach leaves without partners: slam/tracker.h).
  float coarse_reach_m = 0.f;
  // The camera's motion since T_world_previous that the motion prior assumes, where the tracker
  // knows better than the last frame's motion carried on (frames dropped or cut before this one
  // or the last: slam/tracker.h). Empty: the last frame's motion.
  std::optional<Pose> prior_motion = std::nullopt;
  // The frame intervals since T_world_previous the one-frame limits on motion and on the jump
  // away from the guess (IcpParams::max_translation_m, max_jump_m, ...) allow for.
  double limit_intervals = 1.0;
  // The camera's motion over one frame at its median pace over the last second
  // (slam/recent_motion.h), where the tracker knows it: another start for a frame that leaves a
  // direction free (IcpParams::second_start_at_pace).
  std::optional<Pose> pace_motion = std::nullopt;
};

// Host copies of the current model prediction (level 0), for renders.
struct Prediction {
  Image<Vec3f> vertex_world;
  Image<Vec3f> normal_world;  // (0,0,0) = no surface
  Image<Rgb8> color;
};

// What processFrame() carries from one frame to the next besides the volume; a checkpoint saves
// it with the volume's bricks so that a resumed run continues bit for bit.
struct PipelineState {
  int frames_processed = 0;
  int frames_lost = 0;
  Pose T_world_cam = Pose::Identity();
  Pose T_world_model = Pose::Identity();  // camera the tracking prediction was raycast from
  bool has_prediction = false;
  // The prediction was windowed by the depth of the frame fused from its camera (see
  // Pipeline::raycastForTracking); a checkpoint then saves that depth, predictionWindow().
  bool prediction_windowed = false;
  std::optional<Pose> last_given_pose;    // GivenIcp: the recorded pose of the previous frame
  // The camera's motion from the frame before the last tracked one to it (camera frame), for the
  // constant-velocity prediction; identity after a lost frame.
  Pose last_motion = Pose::Identity();
  bool last_frame_committed = false;  // the previous frame ended with a pose (commit, not skip)
  // Bricks fused frames restarted (IcpParams::restart_stale_bricks): the volume no longer holds
  // every observation of them.
  int64_t bricks_restarted = 0;
};

struct IcpKernel;          // fusion/icp_kernels.h
struct PhotometricKernel;  // fusion/photometric_kernels.h

class Pipeline {
 public:
  Pipeline(const PipelineParams& params, const Intrinsics& depth_intrinsics, Device device,
           bool with_classes = false);
  ~Pipeline();
  Pipeline(const Pipeline&) = delete;
  Pipeline& operator=(const Pipeline&) = delete;

  // Fuses one frame. pose_source decides how its pose is found (see PoseSource).
  FrameResult processFrame(const RgbdFrame& frame, PoseSource pose_source = PoseSource::Icp);

  // The same, step by step, for a driver that decides itself which pose to trust and whether to
  // fuse (slam/: relocalisation, probation). A frame is measure()d, then tracked as often as the
  // driver likes, each time from any guess against a prediction from any pose, and ended once,
  // by commit() at a pose or by skip() without one.
  void measure(const RgbdFrame& frame);
  // The tracking prediction raycast from T_world_model (no window) unless it is there already.
  void predictForTracking(const Pose& T_world_model);
  bool hasPrediction() const { return state_.has_prediction; }
  FrameResult track(const Pose& guess, const TrackingCheck& check);
  // Ends the frame at T_world_cam: fuses it when `fuse` (result gets bricks_fused, volume_full,
  // integrated), then raycasts the next prediction from there.
  void commit(const Pose& T_world_cam, bool fuse, FrameResult& result);
  // Ends a frame that has no pose: counted lost; the prediction stays where it was.
  void skip();
  // Ends the measured frame by fusing it at a known pose, with no prediction for a next frame to
  // track against (a second pass at optimised poses).
  void fuseAt(const Pose& T_world_cam, FrameResult& result);

  // Drops the volume and the tracking prediction (the frame counters stay): the next commit()
  // starts a new map. The tracker's way on when the camera was lost where the old map cannot find
  // it again (slam/tracker.h); the maps are joined after the pass, and fused again together.
  void startNewMap();

  // Classes whose pixels are kept out of TSDF integration and ICP (still voted), by class id.
  void setDynamicClasses(const std::vector<int>& class_ids);

  const Pose& pose() const { return state_.T_world_cam; }
  int framesProcessed() const { return state_.frames_processed; }
  int framesLost() const { return state_.frames_lost; }
  Device device() const { return device_; }
  const PipelineParams& params() const { return params_; }
  const Intrinsics& intrinsics() const { return intrinsics_; }
  bool withClasses() const { return with_classes_; }
  const StageTimer& timer() const { return timer_; }
  StageTimer& timer() { return timer_; }

  // Renders of the model from the last pose (or any pose): vertex, normal and color maps.
  Prediction predict(bool with_color);
  Prediction predictFrom(const Pose& T_world_cam, bool with_color);

  // Every allocated brick in host memory (CPU: the live volume; CUDA: a download). Valid until
  // the next processFrame() or hostVolume() call.
  BrickVolumeView hostVolume();
  int brickCount() const;
  // Bytes the backend holds for the volume now.
  size_t volumeBytes() const;
  // Bytes a pipeline allocates on the GPU when it starts (frame buffers, the first brick pool).
  static size_t startupDeviceBytes(const Intrinsics& camera, bool with_classes);

  // Checkpoints (fusion/checkpoint.h): the state to save, and a restore into a pipeline that has
  // processed no frame yet. Restoring raycasts the tracking prediction again from the saved pose,
  // exactly as the last processFrame() left it.
  // A windowed prediction (state().prediction_windowed) also needs the depth that windowed it:
  // predictionWindow() is that image, and restore() takes it back (without it, as when a state
  // is restored only to render the bricks, the prediction is raycast without a window).
  const PipelineState& state() const { return state_; }
  Image<float> predictionWindow() const;
  // brick_stamps: brickStamps() as saved, one per brick (empty: every brick counts as seen by the
  // last frame).
  void restore(const PipelineState& state, const HostBrickVolume& bricks, const Image<float>& window = {},
               const std::vector<uint32_t>& brick_stamps = {});
  // Each brick of hostVolume() (same order): the frame whose marking last listed it (1-based).
  std::vector<uint32_t> brickStamps() const;

 private:
  struct Buffers;
  struct IcpSolution;
  // Tracking (fusion/tracking.cpp): the ICP solve, then the decision whether to trust it.
  // T_hold: the pose the directions the view leaves unconstrained are held at. solvePyramid is
  // the coarse-to-fine solve from initial_guess; where the view leaves directions free,
  // solveAgainFromPrior solves once more from a prior (the motion prior or the camera's pace:
  // IcpParams::second_start_at_prior, second_start_at_pace) and returns that solution where it
  // fits the frame better (finestFit), else nothing.
  IcpSolution solvePyramid(const Pose& initial_guess, const Pose& T_hold, float coarse_reach_m);
  std::optional<IcpSolution> solveAgainFromPrior(const IcpSolution& first, const Pose& T_hold, float coarse_reach_m);
  struct FinestFit;
  FinestFit finestFit(const Pose& T_world_cam) const;
  // The point-to-plane and photometric terms at a pyramid level, without a pose yet.
  IcpKernel icpKernel(int level, float coarse_reach_m) const;
  PhotometricKernel photometricKernel(int level) const;
  // The prediction's pyramid level a measured level associates against.
  int modelLevel(int level) const;
  // How the measured points move under a camera-frame pose increment (fusion/tracking.cpp).
  Eigen::Matrix<double, 6, 6> measuredPointMetric() const;
  FrameResult judgeTracking(const IcpSolution& solution, const Pose& guess, const TrackingCheck& check) const;
  // Fuses the frame into the volume at state_.T_world_cam and fills the result's bricks_fused,
  // bricks_restarted and volume_full (some of its bricks found no slot: the pool was full).
  void integrate(FrameResult& result);
  uint32_t restartBefore(uint32_t stamp) const;  // MarkBricksKernel::restart_before
  // The oldest marking stamp of the tracking model's window (IcpParams::model_window_frames) when
  // `newest` is the newest stamp in it; 0: the whole model.
  uint32_t modelWindowStart(uint32_t newest) const;
  // The depth integration marks and fuses: filtered or raw (IntegrationParams::
  // integrate_filtered_depth), with the dynamic pixels of a labelled frame kept for the vote.
  ImageView<const float> fusedDepth() const;
  // window: look for surfaces only near depth[level] (RaycastKernel::window_depth).
  // min_stamp: see only bricks a frame marked at or after that stamp (VolumeView::min_stamp).
  void raycast(const Pose& T_world_cam, bool with_color, int level, bool window = false, uint32_t min_stamp = 0);
  // The model prediction tracking uses: a raycast from T_world_model, which becomes
  // state_.T_world_model. windowed: the current frame was fused from this pose, and its depth
  // bounds the rays (see the definition).
  void raycastForTracking(const Pose& T_world_model, bool windowed);
  bool photometricActive() const;

  PipelineParams params_;
  Intrinsics intrinsics_;
  Device device_;
  bool with_classes_;
  std::unique_ptr<SparseVolume> volume_;
  std::unique_ptr<Buffers> buffers_;
  PipelineState state_;
  bool has_labels_ = false;
  bool has_color_ = false;
  bool color_full_ = false;  // the frame's colour is larger than depth: integrate from color_full
  bool model_has_intensity_ = false;  // the prediction carries model_intensity
  uint32_t prediction_min_stamp_ = 0;  // the prediction's window of recent bricks (0: all)
  uint32_t last_marking_stamp_ = 0;    // the stamp of the last frame fused
  StageTimer timer_;
};

}  // namespace vf
