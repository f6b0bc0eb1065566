#include "fusion/pipeline.h"

#include <algorithm>
#include <cmath>

#include "core/error.h"
#include "fusion/buffer.h"
#include "fusion/integrate_kernels.h"
#include "fusion/measurement_kernels.h"
#include "fusion/parallel.h"
#include "fusion/photometric_kernels.h"
#include "fusion/pipeline_buffers.h"
#include "fusion/raycast_kernels.h"
#include "fusion/semantic_kernels.h"
#include "fusion/sparse_volume.h"

namespace vf {

Pipeline::Pipeline(const PipelineParams& params, const Intrinsics& depth_intrinsics, Device device,
                   bool with_classes)
    : params_(params), intrinsics_(depth_intrinsics), device_(resolveDevice(device)),
      with_classes_(with_classes) {
  params_.validate();
  validateCamera(intrinsics_);
  params_.volume.truncation_m = params_.volume.truncationOrDefault();
  volume_ = std::make_unique<SparseVolume>(params_.volume, with_classes_, device_);
  buffers_ = std::make_unique<Buffers>(device_, intrinsics_);
}

Pipeline::~Pipeline() = default;

bool Pipeline::photometricActive() const {
  return params_.icp.photometric_weight > 0.f && has_color_ && model_has_intensity_;
}

void Pipeline::setDynamicClasses(const std::vector<int>& class_ids) {
  std::vector<uint8_t> table(65536, 0);
  for (int id : class_ids) {
    if (id < 0 || id > 65535) throw Error("dynamic class id " + std::to_string(id) + " is out of range");
    table[size_t(id)] = 1;
  }
  buffers_->is_dynamic.upload(table.data(), table.size());
}

size_t Pipeline::startupDeviceBytes(const Intrinsics& camera, bool with_classes) {
  // Per pixel: the frame, its three-level pyramids and the model prediction (about 100 bytes,
  // rounded up); room for the reduction scratch and the runtime's own allocations.
  constexpr size_t kBytesPerPixel = 128, kHeadroomBytes = size_t(64) << 20;
  return size_t(camera.width) * size_t(camera.height) * kBytesPerPixel + kHeadroomBytes +
         SparseVolume::initialDeviceBytes(with_classes);
}

int Pipeline::brickCount() const { return volume_->brickCount(); }
size_t Pipeline::volumeBytes() const { return volume_->bytesHeld(); }
BrickVolumeView Pipeline::hostVolume() { return volume_->hostView(); }

void Pipeline::measure(const RgbdFrame& frame) {
  ScopedStage stage(timer_, "measure", device_);
  Buffers& b = *buffers_;
  const int w = intrinsics_.width, h = intrinsics_.height;
  if (frame.depth.width() != w || frame.depth.height() != h)
    throw Error("frame " + frame.name + ": depth is " + std::to_string(frame.depth.width()) + "x" +
                std::to_string(frame.depth.height()) + ", the camera is " + std::to_string(w) + "x" +
                std::to_string(h));
  b.raw_depth.buffer.upload(frame.depth.data(), size_t(w) * h);
  has_color_ = !frame.color.empty();
  if (has_color_) {
    const int cw = frame.color.width(), ch = frame.color.height();
    color_full_ = cw != w || ch != h;
    if (!color_full_) {
      b.color.buffer.upload(frame.color.data(), size_t(w) * h);
    } else {
      // A larger image of the same camera (Record3D: the RGB camera, depth scaled down from it):
      // fused at its own resolution, averaged down to the depth size for everything else.
      const double sx = double(cw) / w, sy = double(ch) / h;
      if (cw < w || ch < h || std::fabs(sx - sy) > 0.02 * sx)
        throw Error("frame " + frame.name + ": colour is " + std::to_string(cw) + "x" + std::to_string(ch) +
                    " and depth " + std::to_string(w) + "x" + std::to_string(h) +
                    ": colour must have the depth's size, or be a larger image of the same view");
      if (b.color_full.width != cw || b.color_full.height != ch) b.color_full.allocate(device_, cw, ch);
      b.color_full.buffer.upload(frame.color.data(), size_t(cw) * ch);
      parallelFor(device_, w * h, DownsampleColorKernel{constView(b.color_full), b.color.view()});
    }
  }
  has_labels_ = !frame.labels.empty();
  ImageView<const float> depth_for_geometry = constView(b.raw_depth);
  if (has_labels_) {
    if (frame.labels.width() != w || frame.labels.height() != h)
      throw Error("frame " + frame.name + ": label map size differs from depth size");
    b.labels.buffer.upload(frame.labels.data(), size_t(w) * h);
    parallelFor(device_, w * h,
                DynamicMaskKernel{constView(b.labels), b.is_dynamic.data(),
                                  params_.dynamic_mask_dilation_px, b.static_mask.view()});
    parallelFor(device_, w * h,
                ApplyMaskKernel{constView(b.raw_depth), constView(b.static_mask), b.static_depth.view()});
    depth_for_geometry = constView(b.static_depth);
  }
  if (has_color_) {
    parallelFor(device_, w * h, IntensityKernel{constView(b.color), b.intensity[0].view()});
    for (int l = 1; l < kPyramidLevels; ++l)
      parallelFor(device_, b.intensity[l].size(),
                  DownsampleIntensityKernel{constView(b.intensity[l - 1]), b.intensity[l].view()});
    for (int l = 0; l < kPyramidLevels; ++l)
      parallelFor(device_, b.intensity[l].size(),
                  IntensityGradientKernel{constView(b.intensity[l]), b.intensity_gradient[l].view()});
  }
  const MeasurementParams& m = params_.measurement;
  BilateralFilterKernel bilateral = BilateralFilterKernel::make(
      m.bilateral_radius_px, m.bilateral_sigma_px, m.bilateral_sigma_m, m.min_depth_m, m.max_depth_m);
  bilateral.depth_in = depth_for_geometry;
  bilateral.depth_out = b.depth[0].view();
  bilateral.pixels_per_item = device_ == Device::Cuda ? 1 : BilateralFilterKernel::kLanes;
  parallelFor(device_, bilateral.itemCount(), bilateral);
  if (has_labels_ && params_.integration.integrate_filtered_depth) {
    bilateral.depth_in = constView(b.raw_depth);
    bilateral.depth_out = b.labelled_filtered_depth.view();
    parallelFor(device_, bilateral.itemCount(), bilateral);
  }
  for (int l = 1; l < kPyramidLevels; ++l)
    parallelFor(device_, b.depth[l].size(),
                DownsampleDepthKernel{constView(b.depth[l - 1]), b.depth[l].view(), m.pyramid_depth_jump_m});
  for (int l = 0; l < kPyramidLevels; ++l) {
    parallelFor(device_, b.depth[l].size(),
                VertexMapKernel{constView(b.depth[l]), b.vertex[l].view(), intrinsics_.atLevel(l)});
    const NormalMapKernel normals{constView(b.vertex[l]), b.normal[l].view(), m.normal_max_jump_m * float(1 << l),
                                  params_.icp.stride_px[size_t(l)]};
    parallelFor(device_, normals.itemCount(), normals);
  }
}

void Pipeline::integrate(FrameResult& result) {
  ScopedStage stage(timer_, "integrate", device_);
  Buffers& b = *buffers_;
  const uint32_t stamp = uint32_t(state_.frames_processed + 1);
  last_marking_stamp_ = stamp;
  const Rigid3f T_world_cam = toRigid3f(state_.T_world_cam);
  const MeasurementParams& m = params_.measurement;
  // Bricks are allocated from the depth that will be fused, with labels including the dynamic
  // pixels, so that their class is still voted.
  const ImageView<const float> depth = fusedDepth();
  SparseVolume& volume = *volume_;
  volume.beginFrame(stamp);
  do {
    MarkBricksKernel mark;
    mark.depth = depth;
    mark.intrinsics = intrinsics_;
    mark.T_world_cam = T_world_cam;
    mark.volume = volume.view();
    mark.min_depth_m = m.min_depth_m;
    mark.max_depth_m = m.max_depth_m;
    mark.stamp = stamp;
    mark.restart_before = restartBefore(stamp);
    mark.restarted = volume.restartedCount();
    mark.frame_entries = volume.frameEntries();
    mark.frame_count = volume.frameCount();
    mark.overflow = volume.overflowFlag();
    mark.tile_px = device_ == Device::Cuda ? 1 : 16;
    parallelFor(device_, mark.itemCount(), mark);
  } while (volume.growIfOverflowed());
  result.bricks_restarted = volume.frameRestarted();
  state_.bricks_restarted += result.bricks_restarted;
  const int touched = volume.assignSlots();
  result.bricks_fused = touched;

  IntegrateKernel kernel;
  kernel.volume = volume.view();
  kernel.slots = volume.frameSlots();
  kernel.slot_count = touched;
  kernel.depth = depth;
  if (has_color_) {
    kernel.color = color_full_ ? constView(b.color_full) : constView(b.color);
    kernel.color_scale_x = float(kernel.color.width) / float(intrinsics_.width);
    kernel.color_scale_y = float(kernel.color.height) / float(intrinsics_.height);
  }
  if (has_labels_) {
    kernel.labels = constView(b.labels);
    kernel.static_mask = constView(b.static_mask);
  }
  kernel.intrinsics = intrinsics_;
  kernel.T_cam_world = toRigid3f(state_.T_world_cam.inverse());
  kernel.min_depth_m = m.min_depth_m;
  kernel.max_depth_m = m.max_depth_m;
  kernel.max_weight = params_.integration.max_weight;
  kernel.probabilistic_vote = params_.integration.class_vote == ClassVote::Probabilistic;
  kernel.vote_seed = params_.integration.class_vote_seed;
  kernel.stamp = stamp;
  parallelFor(device_, touched * IntegrateKernel::kRowsPerBrick, kernel);
  result.volume_full = volume.poolFull();
  result.integrated = true;
}

// The bricks the window of this frame's tracking model did not hold (the newest stamp in it being
// the frame before's), when they are to restart.
uint32_t Pipeline::restartBefore(uint32_t stamp) const {
  return params_.icp.restart_stale_bricks ? modelWindowStart(stamp - 1) : 0u;
}

uint32_t Pipeline::modelWindowStart(uint32_t newest) const {
  const uint32_t window = uint32_t(std::max(0, params_.icp.model_window_frames));
  return window > 0 && newest > window ? newest - window + 1 : 0u;
}

ImageView<const float> Pipeline::fusedDepth() const {
  const Buffers& b = *buffers_;
  if (!params_.integration.integrate_filtered_depth) return constView(b.raw_depth);
  return has_labels_ ? constView(b.labelled_filtered_depth) : constView(b.depth[0]);
}

void Pipeline::raycast(const Pose& T_world_cam, bool with_color, int level, bool window, uint32_t min_stamp) {
  Buffers& b = *buffers_;
  const Intrinsics camera = intrinsics_.atLevel(level);
  const int tiles_x = (camera.width + kRangeTilePx - 1) / kRangeTilePx;
  const int tiles_y = (camera.height + kRangeTilePx - 1) / kRangeTilePx;
  const float near_m = params_.measurement.min_depth_m;
  const float far_m = params_.measurement.max_depth_m + params_.volume.truncation_m;
  parallelFor(device_, tiles_x * tiles_y, ClearRangeKernel{b.range_min.data(), b.range_max.data()});
  BrickRangeKernel range;
  range.volume = volume_->view();
  range.intrinsics = camera;
  range.T_cam_world = toRigid3f(T_world_cam.inverse());
  range.cull = FrustumCull::make(camera, near_m, far_m);
  range.range_min = b.range_min.data();
  range.range_max = b.range_max.data();
  range.tiles_x = tiles_x;
  range.tiles_y = tiles_y;
  const int bricks = volume_->bricksNearView(range.cull, range.T_cam_world, &range.slots);
  parallelFor(device_, bricks, range);

  // The colour buffer is allocated at full size; a coarser raycast uses its first pixels.
  const ImageView<Rgb8> color{b.model_color.buffer.data(), camera.width, camera.height};
  RaycastKernel ray;
  ray.volume = volume_->view();
  ray.volume.min_stamp = min_stamp;
  ray.intrinsics = camera;
  ray.T_world_cam = toRigid3f(T_world_cam);
  ray.near_m = near_m;
  ray.far_m = far_m;
  ray.min_step_vox = params_.raycast.min_step_vox;
  ray.step_fraction = params_.raycast.step_fraction;
  ray.vertex = b.model_vertex[level].view();
  ray.normal = b.model_normal[level].view();
  if (with_color) ray.color = color;
  ray.range_min = b.range_min.data();
  ray.range_max = b.range_max.data();
  ray.tiles_x = tiles_x;
  ray.rays_per_item = device_ == Device::Cuda ? 1 : RaycastKernel::kMaxRaysPerItem;
  if (window) {
    ray.window_depth = constView(b.depth[level]);
    ray.window_m = params_.icp.max_distance_m;
  }
  const int pixels = camera.width * camera.height;
  parallelFor(device_, (pixels + ray.rays_per_item - 1) / ray.rays_per_item, ray);
  if (with_color) {
    parallelFor(device_, camera.width * camera.height,
                IntensityKernel{ImageView<const Rgb8>{color.data, color.width, color.height},
                                b.model_intensity[level].view()});
    for (int l = level + 1; l < kPyramidLevels; ++l)
      parallelFor(device_, b.model_intensity[l].size(),
                  DownsampleModelIntensityKernel{constView(b.model_intensity[l - 1]), b.model_intensity[l].view()});
  }
  for (int l = level + 1; l < kPyramidLevels; ++l)
    parallelFor(device_, b.model_vertex[l].size(),
                DownsamplePredictionKernel{constView(b.model_vertex[l - 1]), constView(b.model_normal[l - 1]),
                                           b.model_vertex[l].view(), b.model_normal[l].view()});
}

FrameResult Pipeline::processFrame(const RgbdFrame& frame, PoseSource pose_source) {
  if (pose_source != PoseSource::Icp && !frame.T_world_cam_given)
    throw Error("frame " + frame.name + " has no recorded pose (PoseSource::Given needs one)");
  measure(frame);
  // Recorded poses are used in their own world frame (gravity-aligned for ARKit and motion
  // capture); ICP alone starts the world at the first camera.
  const std::optional<Pose>& given = frame.T_world_cam_given;
  PipelineState& s = state_;
  FrameResult result;
  if (s.frames_processed == 0 || pose_source == PoseSource::Given) {
    const Pose T = given && pose_source != PoseSource::Icp ? *given : Pose::Identity();
    commit(s.frames_processed == 0 ? T : *given, true, result);
  } else {
    Pose guess = params_.icp.constant_velocity ? s.T_world_cam * s.last_motion : s.T_world_cam;
    if (pose_source == PoseSource::GivenIcp && s.last_given_pose)
      guess = s.T_world_cam * (s.last_given_pose->inverse() * *given);
    result = track(guess, TrackingCheck{s.T_world_cam, false});
    if (result.tracked) {
      commit(result.T_world_cam, true, result);
    } else {
      result.T_world_cam = s.T_world_cam;
      skip();
      // A lost frame was measured from somewhere else: the next one tracks against a prediction
      // from the last good pose that no frame's depth windowed.
      predictForTracking(s.T_world_cam);
    }
  }
  if (given) s.last_given_pose = given;
  return result;
}

void Pipeline::predictForTracking(const Pose& T_world_model) {
  if (state_.has_prediction && !state_.prediction_windowed && state_.T_world_model.matrix() == T_world_model.matrix())
    return;
  ScopedStage stage(timer_, "raycast", device_);
  raycastForTracking(T_world_model, false);
}

void Pipeline::commit(const Pose& T_world_cam, bool fuse, FrameResult& result) {
  PipelineState& s = state_;
  s.last_motion = s.last_frame_committed ? s.T_world_cam.inverse() * T_world_cam : Pose::Identity();
  s.last_frame_committed = true;
  s.T_world_cam = T_world_cam;
  result.T_world_cam = T_world_cam;
  if (fuse) integrate(result);
  {
    ScopedStage stage(timer_, "raycast", device_);
    raycastForTracking(T_world_cam, result.integrated);
  }
  ++s.frames_processed;
}

void Pipeline::fuseAt(const Pose& T_world_cam, FrameResult& result) {
  PipelineState& s = state_;
  s.T_world_cam = T_world_cam;
  s.last_frame_committed = false;
  s.has_prediction = false;
  result.T_world_cam = T_world_cam;
  integrate(result);
  ++s.frames_processed;
}

void Pipeline::startNewMap() {
  volume_.reset();  // before the new one allocates: the two need not fit at once
  volume_ = std::make_unique<SparseVolume>(params_.volume, with_classes_, device_);
  state_.has_prediction = false;
  state_.prediction_windowed = false;
  state_.last_motion = Pose::Identity();
  state_.last_frame_committed = false;
  model_has_intensity_ = false;
  prediction_min_stamp_ = 0;
}

void Pipeline::skip() {
  ++state_.frames_processed;
  ++state_.frames_lost;
  state_.last_frame_committed = false;
  state_.last_motion = Pose::Identity();
}

// The next frame's ICP pairs its points with model points within max_distance_m of them, and
// the camera moves little between frames: a model surface further than that from this frame's
// depth along the same ray would be rejected anyway. So where the frame just fused from this
// pose measured a depth, the rays search only that window around it, not the whole range of
// bricks in view: fr1_xyz 18 -> 12 steps per ray, raycast -13 %, the room scan -22 %, ATE
// unchanged. Where it measured nothing, no ray is cast: ICP pairs only measured points, the
// photometric term only model points that land on measured depth, and the next frame's holes
// are mostly this frame's. A quarter of fr1_xyz's rays (at the prediction level) fell in holes
// and marched the whole range of their bricks, half of all steps; now only those within
// RaycastKernel::kWindowHoleRadiusPx of a measurement march, in its window: raycast 21.7 ->
// 14.6 ms, ATE unchanged on every sequence. A lost frame was measured from somewhere else: its
// prediction is not windowed.
//
// The model tracking sees after a fused frame is what the last IcpParams::model_window_frames
// frames saw (bricks their marking listed), as ElasticFusion tracks against its active surfels
// only: where the walk comes back to a place mapped long ago with drift in between, the old
// walls lie centimetres to decimetres off the new ones and pull the tracker between the two; the
// loop closure joins them instead. After a frame that was not fused (lost, relocalising, on
// probation) the whole model is seen: a pose found again is judged against everything mapped.
void Pipeline::raycastForTracking(const Pose& T_world_model, bool windowed) {
  prediction_min_stamp_ = windowed ? modelWindowStart(last_marking_stamp_) : 0u;
  raycast(T_world_model, params_.icp.photometric_weight > 0.f, params_.raycast.prediction_level, windowed,
          prediction_min_stamp_);
  model_has_intensity_ = params_.icp.photometric_weight > 0.f;
  state_.T_world_model = T_world_model;
  state_.has_prediction = true;
  state_.prediction_windowed = windowed;
}

Prediction Pipeline::predict(bool with_color) { return predictFrom(state_.T_world_cam, with_color); }

Prediction Pipeline::predictFrom(const Pose& T_world_cam, bool with_color) {
  Buffers& b = *buffers_;
  raycast(T_world_cam, with_color, 0);
  Prediction out;
  const int w = intrinsics_.width, h = intrinsics_.height;
  out.vertex_world.resize(w, h);
  out.normal_world.resize(w, h);
  b.model_vertex[0].buffer.download(out.vertex_world.data(), size_t(w) * h);
  b.model_normal[0].buffer.download(out.normal_world.data(), size_t(w) * h);
  if (with_color) {
    out.color.resize(w, h);
    b.model_color.buffer.download(out.color.data(), size_t(w) * h);
  }
  // Restore the tracking prediction if a different pose or level was rendered.
  if (state_.has_prediction)
    raycast(state_.T_world_model, model_has_intensity_, params_.raycast.prediction_level, state_.prediction_windowed,
            prediction_min_stamp_);
  return out;
}

Image<float> Pipeline::predictionWindow() const {
  Image<float> window;
  if (!state_.prediction_windowed) return window;
  const ImageBuffer<float>& depth = buffers_->depth[params_.raycast.prediction_level];
  window.resize(depth.width, depth.height);
  depth.buffer.download(window.data(), size_t(depth.width) * depth.height);
  return window;
}

std::vector<uint32_t> Pipeline::brickStamps() const { return volume_->brickStamps(); }

void Pipeline::restore(const PipelineState& state, const HostBrickVolume& bricks, const Image<float>& window,
                       const std::vector<uint32_t>& brick_stamps) {
  if (state_.frames_processed != 0) throw Error("pipeline: a pipeline can only be restored before its first frame");
  if (state.frames_processed < 0 || state.frames_lost < 0 || state.frames_lost > state.frames_processed)
    throw Error("pipeline: the saved frame counters are inconsistent");
  ImageBuffer<float>& depth = buffers_->depth[params_.raycast.prediction_level];
  const bool windowed = state.prediction_windowed && !window.empty();
  if (windowed && (window.width() != depth.width || window.height() != depth.height))
    throw Error("pipeline: the saved prediction window is " + std::to_string(window.width()) + "x" +
                std::to_string(window.height()) + ", the tracking prediction " + std::to_string(depth.width) + "x" +
                std::to_string(depth.height));
  std::vector<uint32_t> stamps = brick_stamps;
  if (stamps.empty()) stamps.assign(bricks.coords.size(), uint32_t(state.frames_processed));
  volume_->restore(bricks, stamps);
  last_marking_stamp_ = stamps.empty() ? 0u : *std::max_element(stamps.begin(), stamps.end());
  state_ = state;
  // The prediction the next frame tracks against, as the last processFrame() left it.
  if (windowed) depth.buffer.upload(window.data(), size_t(depth.width) * depth.height);
  if (state.has_prediction) raycastForTracking(state.T_world_model, windowed);
}

}  // namespace vf
