#pragma once
// The KinectFusion loop: measure -> track -> integrate -> raycast, per frame, on one backend.
// Owns the volume and every per-frame buffer (allocated once in the constructor).
#include <memory>
#include <optional>
#include <string>
#include <vector>

#include "core/frame.h"
#include "fusion/dense_volume.h"
#include "fusion/device.h"
#include "fusion/params.h"
#include "fusion/stage_timer.h"

namespace vf {

// How the camera pose of each frame is obtained.
enum class PoseSource {
  Icp,       // frame-to-model ICP (KinectFusion)
  Given,     // trust the frame's recorded pose (phones, mocap)
  GivenIcp,  // start ICP from the recorded relative motion and refine
};

struct FrameResult {
  bool tracked = true;      // false: pose rejected, last good pose kept, frame not integrated
  bool integrated = false;
  Pose T_world_cam = Pose::Identity();
  int icp_inliers = 0;
  float icp_inlier_fraction = 0.f;
  float icp_rmse_m = 0.f;
  std::string lost_reason;  // why tracking was rejected
};

// Host copies of the current model prediction (level 0), for renders.
struct Prediction {
  Image<Vec3f> vertex_world;
  Image<Vec3f> normal_world;  // (0,0,0) = no surface
  Image<Rgb8> color;
};

class Pipeline {
 public:
  Pipeline(const PipelineParams& params, const Intrinsics& depth_intrinsics, Device device,
           bool with_classes = false);
  ~Pipeline();
  Pipeline(const Pipeline&) = delete;
  Pipeline& operator=(const Pipeline&) = delete;

  // Fuses one frame. pose_source decides how its pose is found (see PoseSource).
  FrameResult processFrame(const RgbdFrame& frame, PoseSource pose_source = PoseSource::Icp);

  // Classes whose pixels are kept out of TSDF integration and ICP (still voted), by class id.
  void setDynamicClasses(const std::vector<int>& class_ids);

  const Pose& pose() const { return T_world_cam_; }
  int framesProcessed() const { return frames_processed_; }
  int framesLost() const { return frames_lost_; }
  Device device() const { return device_; }
  const PipelineParams& params() const { return params_; }
  const StageTimer& timer() const { return timer_; }
  StageTimer& timer() { return timer_; }

  // Renders of the model from the last pose (or any pose): vertex, normal and color maps.
  Prediction predict(bool with_color);
  Prediction predictFrom(const Pose& T_world_cam, bool with_color);

  // The fused volume in host memory (CPU: the live volume; CUDA: downloaded).
  const DenseVolume& hostVolume();

  // Bytes of memory the backend holds for volume and frame buffers (upper bound, all committed).
  size_t reservedBytes() const;

 private:
  struct Buffers;
  void measure(const RgbdFrame& frame);
  FrameResult track(const Pose& initial_guess);
  void integrate();
  void raycast(const Pose& T_world_cam, bool with_color, int level);
  // The model prediction tracking uses: a raycast from T_world_cam_, which becomes T_world_model_.
  void raycastForTracking();

  // Checkpoints (fusion/pipeline_state.h) save and restore the frame state of this class.
  friend struct PipelineStateAccess;
  // The allocated-brick list (order of first touch), downloaded from / uploaded to the backend;
  // the setter also sets allocated_bricks_.
  std::vector<int> allocatedBrickList() const;
  void setAllocatedBrickList(const std::vector<int>& bricks);
  bool photometricActive() const;

  PipelineParams params_;
  Intrinsics intrinsics_;
  Device device_;
  bool with_classes_;
  std::unique_ptr<Buffers> buffers_;
  DenseVolume host_volume_;
  VolumeView volume_;  // views of the backend's arrays
  Pose T_world_cam_ = Pose::Identity();
  Pose T_world_model_ = Pose::Identity();  // camera the current prediction was raycast from
  std::optional<Pose> first_given_pose_;
  std::optional<Pose> last_given_pose_;
  bool has_prediction_ = false;
  bool has_labels_ = false;
  bool has_color_ = false;
  bool model_has_intensity_ = false;  // the prediction carries model_intensity
  int frames_processed_ = 0;
  int frames_lost_ = 0;
  int allocated_bricks_ = 0;  // length of the allocated-brick list
  StageTimer timer_;
};

}  // namespace vf
