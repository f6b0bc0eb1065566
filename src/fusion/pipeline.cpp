#include "fusion/pipeline.h"

#include <Eigen/Cholesky>
#include <cmath>

#include "core/error.h"
#include "fusion/buffer.h"
#include "fusion/icp_kernels.h"
#include "fusion/integrate_kernels.h"
#include "fusion/measurement_kernels.h"
#include "fusion/parallel.h"
#include "fusion/photometric_kernels.h"
#include "fusion/raycast_kernels.h"
#include "fusion/semantic_kernels.h"

namespace vf {

constexpr int kLevels = 3;

struct Pipeline::Buffers {
  ImageBuffer<float> raw_depth;   // as read (metres)
  ImageBuffer<float> fuse_depth;  // raw depth with dynamic pixels removed
  ImageBuffer<Rgb8> color;
  ImageBuffer<uint16_t> labels;
  ImageBuffer<uint8_t> static_mask;
  Buffer<uint8_t> is_dynamic;     // per class id
  ImageBuffer<float> depth[kLevels];
  ImageBuffer<Vec3f> vertex[kLevels], normal[kLevels];              // measured, camera frame
  ImageBuffer<Vec3f> model_vertex[kLevels], model_normal[kLevels];  // predicted, world frame
  ImageBuffer<Rgb8> model_color;
  ImageBuffer<float> intensity[kLevels];        // current frame, grey in [0, 1]
  ImageBuffer<float> model_intensity[kLevels];  // prediction, -1 where uncoloured
  Buffer<int> brick_list;        // bricks touched by the current frame
  Buffer<int> brick_count;
  Buffer<int> allocated_list;    // bricks touched by any frame, in order of first touch
  Buffer<int> allocated_count;
  Buffer<float> range_min, range_max;  // per-tile ray depth bounds
  // Volume arrays when they live on the GPU (the CPU backend uses host_volume_ directly).
  Buffer<TsdfVoxel> tsdf;
  Buffer<Rgb8> voxel_color;
  Buffer<uint32_t> class_vote;
  Buffer<uint32_t> brick_stamp;
};

namespace {

template <class T>
ImageView<const T> constView(const ImageBuffer<T>& b) {
  return {b.buffer.data(), b.width, b.height};
}

// Left-multiplied increment exp(xi) for xi = (omega, v): rotation by the axis-angle omega and
// translation v.
Pose twistToPose(const Eigen::Matrix<double, 6, 1>& xi) {
  Pose delta = Pose::Identity();
  const Eigen::Vector3d omega = xi.head<3>();
  const double angle = omega.norm();
  if (angle > 1e-12) delta.linear() = Eigen::AngleAxisd(angle, omega / angle).toRotationMatrix();
  delta.translation() = xi.tail<3>();
  return delta;
}

double rotationDeg(const Pose& delta) {
  return Eigen::AngleAxisd(delta.linear()).angle() * 180.0 / M_PI;
}

}  // namespace

Pipeline::Pipeline(const PipelineParams& params, const Intrinsics& depth_intrinsics, Device device,
                   bool with_classes)
    : params_(params), intrinsics_(depth_intrinsics), device_(resolveDevice(device)),
      with_classes_(with_classes), buffers_(std::make_unique<Buffers>()) {
  params_.validate();
  if (!intrinsics_.valid()) throw Error("pipeline: camera intrinsics are not set (fx, fy, size)");
  if ((intrinsics_.width >> (kLevels - 1)) < 8 || (intrinsics_.height >> (kLevels - 1)) < 8)
    throw Error("pipeline: depth images of " + std::to_string(intrinsics_.width) + "x" +
                std::to_string(intrinsics_.height) + " are too small for a 3-level pyramid");
  VolumeSpec& spec = params_.volume;
  spec.truncation_m = spec.truncationOrDefault();
  if (params_.place_like_kinectfusion) {
    const Vec3f extent = spec.extent_m();
    spec.origin_m = {-0.5f * extent.x, -0.5f * extent.y, 0.f};
  }
  // The host volume: the live volume on the CPU, the download target for CUDA.
  host_volume_ = DenseVolume(spec, with_classes_);
  volume_ = host_volume_.view();
  Buffers& b = *buffers_;
  const Device d = device_;
  if (d == Device::Cuda) {
    const size_t n = spec.voxelCount();
    b.tsdf.allocate(d, n);
    b.voxel_color.allocate(d, n);
    if (with_classes_) b.class_vote.allocate(d, n);
    b.brick_stamp.allocate(d, size_t(volume_.brickCount()));
    volume_.tsdf = b.tsdf.data();
    volume_.color = b.voxel_color.data();
    volume_.class_vote = with_classes_ ? b.class_vote.data() : nullptr;
    volume_.brick_stamp = b.brick_stamp.data();
  }
  const int w = intrinsics_.width, h = intrinsics_.height;
  b.raw_depth.allocate(d, w, h);
  b.fuse_depth.allocate(d, w, h);
  b.color.allocate(d, w, h);
  b.labels.allocate(d, w, h);
  b.static_mask.allocate(d, w, h);
  b.is_dynamic.allocate(d, 65536);
  for (int l = 0; l < kLevels; ++l) {
    b.depth[l].allocate(d, w >> l, h >> l);
    b.vertex[l].allocate(d, w >> l, h >> l);
    b.normal[l].allocate(d, w >> l, h >> l);
    b.model_vertex[l].allocate(d, w >> l, h >> l);
    b.model_normal[l].allocate(d, w >> l, h >> l);
    b.intensity[l].allocate(d, w >> l, h >> l);
    b.model_intensity[l].allocate(d, w >> l, h >> l);
  }
  b.model_color.allocate(d, w, h);
  b.brick_list.allocate(d, size_t(volume_.brickCount()));
  b.brick_count.allocate(d, 1);
  b.allocated_list.allocate(d, size_t(volume_.brickCount()));
  b.allocated_count.allocate(d, 1);
  const size_t full_resolution_tiles =
      size_t((w + kRangeTilePx - 1) / kRangeTilePx) * size_t((h + kRangeTilePx - 1) / kRangeTilePx);
  b.range_min.allocate(d, full_resolution_tiles);
  b.range_max.allocate(d, full_resolution_tiles);
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

size_t Pipeline::reservedBytes() const {
  return params_.volume.voxelCount() * DenseVolume::bytesPerVoxel(with_classes_);
}

void Pipeline::measure(const RgbdFrame& frame) {
  ScopedStage stage(timer_, "measure");
  Buffers& b = *buffers_;
  const int w = intrinsics_.width, h = intrinsics_.height;
  if (frame.depth.width() != w || frame.depth.height() != h)
    throw Error("frame " + frame.name + ": depth is " + std::to_string(frame.depth.width()) + "x" +
                std::to_string(frame.depth.height()) + ", the camera is " + std::to_string(w) + "x" +
                std::to_string(h));
  b.raw_depth.buffer.upload(frame.depth.data(), size_t(w) * h);
  has_color_ = !frame.color.empty();
  if (has_color_) {
    if (frame.color.width() != w || frame.color.height() != h)
      throw Error("frame " + frame.name + ": color size differs from depth size");
    b.color.buffer.upload(frame.color.data(), size_t(w) * h);
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
                ApplyMaskKernel{constView(b.raw_depth), constView(b.static_mask), b.fuse_depth.view()});
    depth_for_geometry = constView(b.fuse_depth);
  }
  if (has_color_) {
    parallelFor(device_, w * h, IntensityKernel{constView(b.color), b.intensity[0].view()});
    for (int l = 1; l < kLevels; ++l)
      parallelFor(device_, b.intensity[l].size(),
                  DownsampleIntensityKernel{constView(b.intensity[l - 1]), b.intensity[l].view()});
  }
  const MeasurementParams& m = params_.measurement;
  BilateralFilterKernel bilateral = BilateralFilterKernel::make(
      m.bilateral_radius_px, m.bilateral_sigma_px, m.bilateral_sigma_m, m.min_depth_m, m.max_depth_m);
  bilateral.depth_in = depth_for_geometry;
  bilateral.depth_out = b.depth[0].view();
  parallelFor(device_, w * h, bilateral);
  for (int l = 1; l < kLevels; ++l)
    parallelFor(device_, b.depth[l].size(),
                DownsampleDepthKernel{constView(b.depth[l - 1]), b.depth[l].view(), m.pyramid_depth_jump_m});
  for (int l = 0; l < kLevels; ++l) {
    parallelFor(device_, b.depth[l].size(),
                VertexMapKernel{constView(b.depth[l]), b.vertex[l].view(), intrinsics_.atLevel(l)});
    parallelFor(device_, b.depth[l].size(),
                NormalMapKernel{constView(b.vertex[l]), b.normal[l].view(), m.normal_max_jump_m * float(1 << l)});
  }
}

FrameResult Pipeline::track(const Pose& initial_guess) {
  ScopedStage stage(timer_, "track");
  Buffers& b = *buffers_;
  const IcpParams& p = params_.icp;
  FrameResult result;
  Pose T = initial_guess;
  const Rigid3f T_model_world = toRigid3f(T_world_model_.inverse());
  // The prediction exists from params_.raycast.prediction_level down; finer measured levels
  // associate against it (projective association only needs the model's camera).
  auto modelLevel = [&](int l) { return std::max(l, params_.raycast.prediction_level); };
  auto icpAtLevel = [&](int l) {
    IcpKernel icp;
    icp.vertex_cam = constView(b.vertex[l]);
    icp.normal_cam = constView(b.normal[l]);
    icp.model_vertex = constView(b.model_vertex[modelLevel(l)]);
    icp.model_normal = constView(b.model_normal[modelLevel(l)]);
    icp.model_intrinsics = intrinsics_.atLevel(modelLevel(l));
    icp.T_model_world = T_model_world;
    icp.max_distance_m = p.max_distance_m;
    icp.min_normal_cos = std::cos(p.max_normal_angle_deg * float(M_PI) / 180.f);
    icp.huber_m = p.huber_m;
    icp.stride_px = l == 0 ? p.finest_stride_px : 1;
    return icp;
  };
  // Geometric sums of the last finest-level iteration: the tracking-loss statistics. They
  // describe the pose before that iteration's (converged, tiny) update, which saves a pass.
  std::array<double, kIcpRowSize> sums{};
  bool have_finest_sums = false;
  for (int l = kLevels - 1; l >= 0; --l) {
    IcpKernel icp = icpAtLevel(l);
    PhotometricKernel photo;
    const bool use_photometric = photometricActive() && l >= p.photometric_finest_level;
    if (use_photometric) {
      photo.model_vertex = constView(b.model_vertex[modelLevel(l)]);
      photo.model_normal = constView(b.model_normal[modelLevel(l)]);
      photo.model_intensity = constView(b.model_intensity[modelLevel(l)]);
      photo.intensity = constView(b.intensity[l]);
      photo.depth = constView(b.depth[l]);
      photo.intrinsics = intrinsics_.atLevel(l);
      photo.weight = p.photometric_weight;
      photo.huber = p.photometric_huber;
      photo.stride_px = modelLevel(l) == 0 ? p.photometric_stride_px : 1;
    }
    for (int it = 0; it < p.iterations[l]; ++it) {
      icp.T_world_cam = toRigid3f(T);
      sums = parallelReduce<kIcpRowSize>(device_, icp.count(), icp);
      have_finest_sums = l == 0;
      if (sums[28] < 6) break;
      std::array<double, kIcpRowSize> system = sums;
      if (use_photometric) {
        photo.T_world_cam = icp.T_world_cam;
        photo.T_cam_world = toRigid3f(T.inverse());
        const auto photometric = parallelReduce<kIcpRowSize>(device_, photo.count(), photo);
        for (int k = 0; k < 27; ++k) system[k] += photometric[k];
      }
      Eigen::Matrix<double, 6, 6> A;
      Eigen::Matrix<double, 6, 1> rhs;
      int k = 0;
      for (int r = 0; r < 6; ++r)
        for (int c = r; c < 6; ++c) A(r, c) = A(c, r) = system[k++];
      for (int r = 0; r < 6; ++r) rhs(r) = -system[k++];
      const Eigen::Matrix<double, 6, 1> xi = A.ldlt().solve(rhs);
      if (!xi.allFinite()) break;
      T = twistToPose(xi) * T;
      if (xi.head<3>().norm() < 1e-6 && xi.tail<3>().norm() < 1e-6) break;  // converged
    }
  }
  if (!have_finest_sums) {  // no finest-level iteration ran: measure the final pose there
    IcpKernel icp = icpAtLevel(0);
    icp.T_world_cam = toRigid3f(T);
    sums = parallelReduce<kIcpRowSize>(device_, icp.count(), icp);
  }
  result.icp_inliers = int(sums[28]);
  result.icp_rmse_m = sums[28] > 0 ? float(std::sqrt(sums[27] / sums[28])) : 0.f;
  result.T_world_cam = T;
  // The fraction is relative to the measured pixels that have a normal (what ICP can use).
  const int measured = int(sums[29]);
  result.icp_inlier_fraction = measured > 0 ? float(result.icp_inliers) / float(measured) : 0.f;
  const Pose motion = T_world_cam_.inverse() * T;
  char why[160] = "";
  if (measured == 0) std::snprintf(why, sizeof(why), "no valid depth");
  else if (!T.matrix().allFinite()) std::snprintf(why, sizeof(why), "ICP diverged");
  else if (result.icp_inlier_fraction < p.min_inlier_fraction)
    std::snprintf(why, sizeof(why), "only %.0f%% of pixels matched the model (min %.0f%%)",
                  100.f * result.icp_inlier_fraction, 100.f * p.min_inlier_fraction);
  else if (result.icp_rmse_m > p.max_rmse_m)
    std::snprintf(why, sizeof(why), "residual %.1f mm above %.1f mm", 1e3f * result.icp_rmse_m, 1e3f * p.max_rmse_m);
  else if (motion.translation().norm() > p.max_translation_m)
    std::snprintf(why, sizeof(why), "moved %.2f m in one frame", motion.translation().norm());
  else if (rotationDeg(motion) > p.max_rotation_deg)
    std::snprintf(why, sizeof(why), "turned %.1f deg in one frame", rotationDeg(motion));
  result.lost_reason = why;
  result.tracked = result.lost_reason.empty();
  return result;
}

void Pipeline::integrate() {
  ScopedStage stage(timer_, "integrate");
  Buffers& b = *buffers_;
  const uint32_t stamp = uint32_t(frames_processed_ + 1);
  const Rigid3f T_world_cam = toRigid3f(T_world_cam_);
  const ImageView<const float> depth =
      params_.integration.integrate_filtered_depth ? constView(b.depth[0])
                                                   : (has_labels_ ? constView(b.fuse_depth) : constView(b.raw_depth));
  // Bricks are marked from the depth that will be fused, plus, with labels, from the dynamic
  // pixels too so that their class is still voted.
  MarkBricksKernel mark;
  mark.depth = has_labels_ ? constView(b.raw_depth) : depth;
  mark.intrinsics = intrinsics_;
  mark.T_world_cam = T_world_cam;
  mark.volume = volume_;
  mark.stamp = stamp;
  mark.allocated_list = b.allocated_list.data();
  mark.allocated_count = b.allocated_count.data();
  const int cols = (intrinsics_.width + mark.stride_px - 1) / mark.stride_px;
  const int rows = (intrinsics_.height + mark.stride_px - 1) / mark.stride_px;
  parallelFor(device_, cols * rows, mark);
  b.allocated_count.download(&allocated_bricks_, 1);

  b.brick_count.zero();
  parallelFor(device_, volume_.brickCount(),
              CollectBricksKernel{volume_.brick_stamp, stamp, b.brick_count.data(), b.brick_list.data()});
  int brick_count = 0;
  b.brick_count.download(&brick_count, 1);

  IntegrateKernel kernel;
  kernel.volume = volume_;
  kernel.bricks = b.brick_list.data();
  kernel.depth = has_labels_ ? constView(b.raw_depth) : depth;
  if (has_color_) kernel.color = constView(b.color);
  if (has_labels_) {
    kernel.labels = constView(b.labels);
    kernel.static_mask = constView(b.static_mask);
  }
  kernel.intrinsics = intrinsics_;
  kernel.T_cam_world = toRigid3f(T_world_cam_.inverse());
  kernel.max_weight = params_.integration.max_weight;
  kernel.probabilistic_vote = params_.integration.class_vote == ClassVote::Probabilistic;
  kernel.vote_seed = params_.integration.class_vote_seed;
  kernel.stamp = stamp;
  parallelFor(device_, brick_count * IntegrateKernel::kRowsPerBrick, kernel);
}

void Pipeline::raycast(const Pose& T_world_cam, bool with_color, int level) {
  Buffers& b = *buffers_;
  const Intrinsics camera = intrinsics_.atLevel(level);
  const int tiles_x = (camera.width + kRangeTilePx - 1) / kRangeTilePx;
  const int tiles_y = (camera.height + kRangeTilePx - 1) / kRangeTilePx;
  parallelFor(device_, tiles_x * tiles_y, ClearRangeKernel{b.range_min.data(), b.range_max.data()});
  BrickRangeKernel range;
  range.volume = volume_;
  range.bricks = b.allocated_list.data();
  range.intrinsics = camera;
  range.T_cam_world = toRigid3f(T_world_cam.inverse());
  range.near_m = params_.measurement.min_depth_m;
  range.range_min = b.range_min.data();
  range.range_max = b.range_max.data();
  range.tiles_x = tiles_x;
  range.tiles_y = tiles_y;
  parallelFor(device_, allocated_bricks_, range);

  // The colour buffer is allocated at full size; a coarser raycast uses its first pixels.
  const ImageView<Rgb8> color{b.model_color.buffer.data(), camera.width, camera.height};
  RaycastKernel ray;
  ray.volume = volume_;
  ray.intrinsics = camera;
  ray.T_world_cam = toRigid3f(T_world_cam);
  ray.near_m = params_.measurement.min_depth_m;
  ray.far_m = params_.measurement.max_depth_m + params_.volume.truncation_m;
  ray.min_step_vox = params_.raycast.min_step_vox;
  ray.step_fraction = params_.raycast.step_fraction;
  ray.vertex = b.model_vertex[level].view();
  ray.normal = b.model_normal[level].view();
  if (with_color) ray.color = color;
  ray.range_min = b.range_min.data();
  ray.range_max = b.range_max.data();
  ray.tiles_x = tiles_x;
  parallelFor(device_, camera.width * camera.height, ray);
  if (with_color) {
    parallelFor(device_, camera.width * camera.height,
                IntensityKernel{ImageView<const Rgb8>{color.data, color.width, color.height},
                                b.model_intensity[level].view()});
    for (int l = level + 1; l < kLevels; ++l)
      parallelFor(device_, b.model_intensity[l].size(),
                  DownsampleModelIntensityKernel{constView(b.model_intensity[l - 1]), b.model_intensity[l].view()});
  }
  for (int l = level + 1; l < kLevels; ++l)
    parallelFor(device_, b.model_vertex[l].size(),
                DownsamplePredictionKernel{constView(b.model_vertex[l - 1]), constView(b.model_normal[l - 1]),
                                           b.model_vertex[l].view(), b.model_normal[l].view()});
}

FrameResult Pipeline::processFrame(const RgbdFrame& frame, PoseSource pose_source) {
  if (pose_source != PoseSource::Icp && !frame.T_world_cam_given)
    throw Error("frame " + frame.name + " has no recorded pose; use --poses icp");
  measure(frame);
  // The world frame is the first frame's camera; recorded poses are re-expressed in it.
  std::optional<Pose> given;
  if (frame.T_world_cam_given) {
    if (!first_given_pose_) first_given_pose_ = *frame.T_world_cam_given;
    given = first_given_pose_->inverse() * *frame.T_world_cam_given;
  }
  FrameResult result;
  result.T_world_cam = T_world_cam_;
  if (frames_processed_ == 0) {
    T_world_cam_ = given && pose_source != PoseSource::Icp ? *given : Pose::Identity();
    result.T_world_cam = T_world_cam_;
  } else if (pose_source == PoseSource::Given) {
    T_world_cam_ = *given;
    result.T_world_cam = T_world_cam_;
  } else {
    Pose guess = T_world_cam_;
    if (pose_source == PoseSource::GivenIcp && last_given_pose_)
      guess = T_world_cam_ * (last_given_pose_->inverse() * *given);
    result = has_prediction_ ? track(guess) : FrameResult{};
    if (!has_prediction_) {
      result.tracked = false;
      result.lost_reason = "no model prediction yet";
    }
    if (result.tracked) T_world_cam_ = result.T_world_cam;
    else {
      ++frames_lost_;
      result.T_world_cam = T_world_cam_;
    }
  }
  if (given) last_given_pose_ = given;
  if (result.tracked) {
    integrate();
    result.integrated = true;
  }
  {
    ScopedStage stage(timer_, "raycast");
    raycastForTracking();
  }
  ++frames_processed_;
  return result;
}

void Pipeline::raycastForTracking() {
  raycast(T_world_cam_, params_.icp.photometric_weight > 0.f, params_.raycast.prediction_level);
  model_has_intensity_ = params_.icp.photometric_weight > 0.f;
  T_world_model_ = T_world_cam_;
  has_prediction_ = true;
}

Prediction Pipeline::predict(bool with_color) { return predictFrom(T_world_cam_, with_color); }

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
  // Restore the tracking prediction if a different pose was rendered.
  if (has_prediction_ && !(T_world_cam.matrix() == T_world_model_.matrix()))
    raycast(T_world_model_, model_has_intensity_, params_.raycast.prediction_level);
  return out;
}

const DenseVolume& Pipeline::hostVolume() {
  if (device_ == Device::Cuda) {
    Buffers& b = *buffers_;
    const VolumeView& host = host_volume_.view();
    b.brick_stamp.download(host.brick_stamp, size_t(host.brickCount()));
    // Copy only the observed bricks (the rest is zero on both sides), one copy per run of
    // consecutive bricks rather than one per brick.
    const std::vector<int> bricks = host_volume_.observedBricks();
    for (size_t i = 0; i < bricks.size();) {
      size_t j = i + 1;
      while (j < bricks.size() && bricks[j] == bricks[j - 1] + 1) ++j;
      const size_t first = size_t(bricks[i]) * kBrickVoxels, count = (j - i) * kBrickVoxels;
      cuda::copyToHost(host.tsdf + first, b.tsdf.data() + first, count * sizeof(TsdfVoxel));
      cuda::copyToHost(host.color + first, b.voxel_color.data() + first, count * sizeof(Rgb8));
      if (host.class_vote)
        cuda::copyToHost(host.class_vote + first, b.class_vote.data() + first, count * sizeof(uint32_t));
      i = j;
    }
  }
  return host_volume_;
}

std::vector<int> Pipeline::allocatedBrickList() const {
  std::vector<int> bricks(static_cast<size_t>(allocated_bricks_));
  buffers_->allocated_list.download(bricks.data(), bricks.size());
  return bricks;
}

void Pipeline::setAllocatedBrickList(const std::vector<int>& bricks) {
  if (bricks.size() > buffers_->allocated_list.size())
    throw Error("pipeline: " + std::to_string(bricks.size()) + " allocated bricks do not fit a volume of " +
                std::to_string(buffers_->allocated_list.size()));
  allocated_bricks_ = int(bricks.size());
  buffers_->allocated_list.upload(bricks.data(), bricks.size());
  buffers_->allocated_count.upload(&allocated_bricks_, 1);
}

}  // namespace vf
