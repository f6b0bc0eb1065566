// Numbers the fusion stages must reproduce on analytic scenes with known answers.
#include <gtest/gtest.h>

#include <tbb/global_control.h>

#include <algorithm>
#include <array>
#include <chrono>
#include <functional>
#include <limits>
#include <set>
#include <string>
#include <thread>
#include <tuple>
#include <random>
#include <vector>

#include "brick_lookup.h"
#include "icp_rows_fixture.h"
#include "core/error.h"
#include "fusion/brick_chunks.h"
#include "fusion/icp_kernels.h"
#include "fusion/measurement_kernels.h"
#include "fusion/parallel.h"
#include "fusion/pipeline.h"
#include "fusion/raycast_kernels.h"
#include "fusion/stage_timer.h"
#include "synthetic_scene.h"
#include "test_data.h"

namespace vf {
namespace {

using test::BrickLookup;
using test::poseFrom;
using test::roomCorner;
using test::SyntheticScene;
using test::testCamera;

PipelineParams withVoxel(float voxel_size_m) {
  PipelineParams p;
  p.volume.voxel_size_m = voxel_size_m;
  return p;
}

// Normalised TSDF along the voxel column through (x, y), interpolated to the zero crossing.
double zeroCrossingZ(const BrickLookup& v, int x, int y, int z_end) {
  for (int z = 0; z + 1 < z_end; ++z) {
    const TsdfVoxel a = v.tsdf(x, y, z), b = v.tsdf(x, y, z + 1);
    if (a.weight == 0 || b.weight == 0) continue;
    const double sa = a.tsdf, sb = b.tsdf;
    if (sa > 0 && sb <= 0) {
      const double t = sa / (sa - sb);
      return v.voxelCenter(x, y, z).z + t * v.view().voxel_size_m;
    }
  }
  return NAN;
}

// Every voxel of `a` equals the voxel at the same coordinate in `b`, and both hold the same bricks.
void expectSameVoxels(const BrickLookup& a, const BrickLookup& b) {
  ASSERT_EQ(a.brickCount(), b.brickCount());
  const BrickVolumeView& va = a.view();
  size_t differing = 0;
  for (size_t n = 0; n < va.brick_count; ++n) {
    const Vec3i c = va.coords[n];
    ASSERT_TRUE(b.hasBrick(c)) << "brick " << c.x << "," << c.y << "," << c.z;
    for (int i = 0; i < kBrickVoxels; ++i) {
      const Vec3i o = localVoxelOffset(i);
      const int64_t j = b.find(c.x * kBrickSize + o.x, c.y * kBrickSize + o.y, c.z * kBrickSize + o.z);
      const TsdfVoxel x = va.tsdf[n * kBrickVoxels + i], y = b.view().tsdf[j];
      const Rgb8 cx = va.color[n * kBrickVoxels + i], cy = b.view().color[j];
      differing += x.tsdf != y.tsdf || x.weight != y.weight || cx.r != cy.r || cx.g != cy.g || cx.b != cy.b ||
                   cx.a != cy.a;
    }
  }
  EXPECT_EQ(differing, 0u);
}

TEST(Integration, PlaneAtHalfMetreHasItsZeroCrossingThereWithinHalfAVoxel) {
  SyntheticScene plane;
  plane.planes.push_back({Eigen::Vector3d(0, 0, -1), -0.5});  // z = 0.5 m
  const Intrinsics k = testCamera();
  const float voxel = 1.0f / 128;
  Pipeline pipeline(withVoxel(voxel), k, Device::Cpu);
  for (int i = 0; i < 3; ++i) pipeline.processFrame(plane.render(k, Pose::Identity()));
  const BrickLookup v(pipeline.hostVolume());
  int checked = 0;
  // Columns on both sides of the optical axis: negative voxel coordinates are as good as any.
  for (int y = -24; y < 26; y += 7)
    for (int x = -24; x < 26; x += 7) {
      const double z = zeroCrossingZ(v, x, y, 128);
      ASSERT_TRUE(std::isfinite(z)) << "no zero crossing in column " << x << "," << y;
      EXPECT_NEAR(z, 0.5, 0.5 * voxel);
      ++checked;
    }
  EXPECT_GT(checked, 40);
  EXPECT_EQ(pipeline.framesLost(), 0);
}

// Far readings of a Kinect-like sensor scatter by centimetres from pixel to pixel. Fusing the
// bilateral-filtered depth (the default) averages that scatter over the filter's window as well
// as over frames; the raw depth only over frames, so its surface stays grainy and its band of
// bricks spreads.
TEST(Integration, FusingTheFilteredDepthSmoothsPixelNoiseThatRawDepthKeeps) {
  SyntheticScene plane;
  plane.planes.push_back({Eigen::Vector3d(0, 0, -1), -3.0});  // z = 3 m
  const Intrinsics k = testCamera();
  const float voxel = VolumeSpec{}.voxel_size_m;
  struct Fused {
    double rms_m;
    size_t bricks;
  };
  const auto fuse = [&](bool filtered) {
    PipelineParams params = withVoxel(voxel);
    params.integration.integrate_filtered_depth = filtered;
    Pipeline pipeline(params, k, Device::Cpu);
    std::mt19937 rng(7);
    std::normal_distribution<float> noise(0.f, 0.015f);  // Kinect v1 at 3 m
    for (int i = 0; i < 10; ++i) {
      RgbdFrame frame = plane.render(k, Pose::Identity());
      for (int p = 0; p < k.width * k.height; ++p) frame.depth.data()[p] += noise(rng);
      frame.T_world_cam_given = Pose::Identity();
      pipeline.processFrame(frame, PoseSource::Given);
    }
    const BrickLookup v(pipeline.hostVolume());
    double sum_sq = 0;
    int columns = 0;
    for (int y = -60; y <= 60; y += 3)
      for (int x = -60; x <= 60; x += 3) {
        const double z = zeroCrossingZ(v, x, y, 600);
        if (!std::isfinite(z)) continue;
        sum_sq += (z - 3.0) * (z - 3.0);
        ++columns;
      }
    EXPECT_GT(columns, 1600) << (filtered ? "filtered" : "raw");
    return Fused{std::sqrt(sum_sq / std::max(columns, 1)), v.brickCount()};
  };
  const Fused raw = fuse(false), filtered = fuse(true);
  std::printf("zero crossing rms: raw %.2f mm, filtered %.2f mm; bricks: raw %zu, filtered %zu\n", raw.rms_m * 1e3,
              filtered.rms_m * 1e3, raw.bricks, filtered.bricks);
  // Measured: raw 5.3 mm, filtered 1.35 mm; bricks 27.6 k against 20.4 k.
  EXPECT_LT(filtered.rms_m, 0.4 * raw.rms_m);
  EXPECT_LT(filtered.rms_m, 0.4 * voxel);
  EXPECT_LT(filtered.bricks, raw.bricks);
}

// The CPU filters eight pixels at a time in vector lanes, CUDA one per thread; integration fuses
// the filtered depth, so CPU/CUDA voxel parity needs the two to give the same bits. Depth with
// noise, steps, holes and readings out of range, on an image whose width is not a multiple of 8.
TEST(Measurement, TheBilateralFilterGivesTheSameBitsEightLanesOrOnePixelAtATime) {
  const int w = 101, h = 37;
  std::vector<float> depth(size_t(w) * h);
  std::mt19937 rng(3);
  std::normal_distribution<float> noise(0.f, 0.01f);
  std::uniform_int_distribution<int> pick(0, 19);
  for (int y = 0; y < h; ++y)
    for (int x = 0; x < w; ++x) {
      float d = 1.5f + 0.01f * float(x) + (x > 60 ? 0.4f : 0.f) + noise(rng);
      const int p = pick(rng);
      if (p == 0) d = 0.f;  // a hole
      if (p == 1) d = 9.f;  // beyond the maximum depth
      depth[size_t(y) * w + size_t(x)] = d;
    }
  const MeasurementParams m;
  const auto filter = [&](int pixels_per_item) {
    std::vector<float> out(depth.size(), -1.f);
    BilateralFilterKernel k = BilateralFilterKernel::make(m.bilateral_radius_px, m.bilateral_sigma_px,
                                                          m.bilateral_sigma_m, m.min_depth_m, m.max_depth_m);
    k.depth_in = ImageView<const float>{depth.data(), w, h};
    k.depth_out = ImageView<float>{out.data(), w, h};
    k.pixels_per_item = pixels_per_item;
    parallelFor(Device::Cpu, k.itemCount(), k);
    return out;
  };
  const std::vector<float> lanes = filter(BilateralFilterKernel::kLanes), single = filter(1);
  int differing = 0, filtered = 0;
  for (size_t i = 0; i < depth.size(); ++i) {
    differing += std::memcmp(&lanes[i], &single[i], sizeof(float)) != 0;
    filtered += single[i] > 0.f && single[i] != depth[i];
  }
  EXPECT_EQ(differing, 0);
  EXPECT_GT(filtered, w * h / 2);  // the filter did smooth most pixels
}

TEST(Raycast, FusedSphereIsFoundAtItsRadiusWithinOneVoxel) {
  SyntheticScene scene;
  const Eigen::Vector3d center(0.05, -0.03, 0.9);
  const double radius = 0.25;
  scene.spheres.push_back({center, radius});
  const Intrinsics k = testCamera();
  Pipeline pipeline(withVoxel(2.0f / 256), k, Device::Cpu);
  const Pose pose = Pose::Identity();
  pipeline.processFrame(scene.render(k, pose), PoseSource::Icp);
  const Prediction pred = pipeline.predictFrom(pose, false);
  const double voxel = 2.0 / 256;
  int hits = 0;
  double worst = 0;
  for (int y = 0; y < k.height; ++y)
    for (int x = 0; x < k.width; ++x) {
      const Vec3f n = pred.normal_world(x, y);
      if (n.x == 0 && n.y == 0 && n.z == 0) continue;
      const Vec3f p = pred.vertex_world(x, y);
      const double r = (Eigen::Vector3d(p.x, p.y, p.z) - center).norm();
      worst = std::max(worst, std::abs(r - radius));
      // The normal points out of the sphere (towards the camera side).
      const Eigen::Vector3d outward = (Eigen::Vector3d(p.x, p.y, p.z) - center).normalized();
      EXPECT_GT(outward.dot(Eigen::Vector3d(n.x, n.y, n.z)), 0.9);
      ++hits;
    }
  EXPECT_GT(hits, 10000);
  EXPECT_LE(worst, voxel) << "largest radius error over " << hits << " pixels";
}

TEST(Tracking, IcpRecoversAKnownSixDofMotionWithinAMillimetreAndATenthOfADegree) {
  const SyntheticScene scene = roomCorner();
  const Intrinsics k = testCamera(320, 240);
  Pipeline pipeline(withVoxel(2.5f / 256), k, Device::Cpu);
  const Pose truth = poseFrom(1.2, -1.5, 0.8, 0.015, -0.01, 0.02);
  pipeline.processFrame(scene.render(k, Pose::Identity()));
  const FrameResult r = pipeline.processFrame(scene.render(k, truth));
  ASSERT_TRUE(r.tracked) << r.lost_reason;
  const Pose error = truth.inverse() * r.T_world_cam;
  EXPECT_LT(error.translation().norm(), 1e-3);
  EXPECT_LT(Eigen::AngleAxisd(error.linear()).angle() * 180 / M_PI, 0.1);
}

// A frame of `scene` seen from `truth` and fused where the camera claims it was (`claimed`): where
// the two differ, the map drifts. A blank frame has no depth (the camera looks elsewhere).
FrameResult fuseClaimingPose(Pipeline& pipeline, const SyntheticScene& scene, const Intrinsics& k, const Pose& truth,
                             const Pose& claimed, bool blank = false) {
  RgbdFrame frame = scene.render(k, truth);
  if (blank) std::fill(frame.depth.data(), frame.depth.data() + k.width * k.height, 0.f);
  frame.T_world_cam_given = claimed;
  return pipeline.processFrame(frame, PoseSource::Given);
}

// Where a walk comes back after drifting, the map holds the place twice: the copy fused long ago
// and the one recent frames fused, centimetres apart. Tracking against both pulls the camera
// between them; with IcpParams::model_window_frames the tracking prediction after a fused frame
// holds only bricks the last frames' marking listed. Here a room corner is fused 20 times, then
// 6 times from 8 cm further back while claiming the same pose (the drift: the old copy now lies
// 8 cm in front of the recent one), then tracked from there. A run resumed from the state at
// that point (with the bricks' stamps, as a checkpoint keeps them) tracks the same.
TEST(Tracking, AnOldCopyOfTheMapOutsideTheModelWindowDoesNotPullTracking) {
  const SyntheticScene scene = roomCorner();
  const Intrinsics k = testCamera(160, 120);
  const Pose mapped = Pose::Identity();
  const Pose drifted = poseFrom(0, 0, 0, 0, 0, -0.08);
  auto fuseWithDrift = [&](Pipeline& pipeline) {
    for (int i = 0; i < 26; ++i) fuseClaimingPose(pipeline, scene, k, i < 20 ? mapped : drifted, mapped);
  };
  PipelineParams windowed_params = withVoxel(0.005f);
  windowed_params.icp.model_window_frames = 3;
  Pipeline windowed(windowed_params, k, Device::Cpu);
  fuseWithDrift(windowed);
  const std::vector<uint32_t> stamps = windowed.brickStamps();
  EXPECT_EQ(*std::max_element(stamps.begin(), stamps.end()), 26u);
  EXPECT_GT(std::count_if(stamps.begin(), stamps.end(), [](uint32_t s) { return s <= 20; }), 100);
  Pipeline resumed(windowed_params, k, Device::Cpu);
  resumed.restore(windowed.state(), HostBrickVolume::copyOf(windowed.hostVolume()), windowed.predictionWindow(),
                  stamps);
  EXPECT_EQ(resumed.brickStamps(), stamps);

  // The recent copy puts the camera where the last frames were: at `mapped` (3.8 mm off).
  const FrameResult recent = windowed.processFrame(scene.render(k, drifted), PoseSource::Icp);
  ASSERT_TRUE(recent.tracked) << recent.lost_reason;
  EXPECT_LT((recent.T_world_cam.translation() - mapped.translation()).norm(), 0.01);
  const FrameResult resumed_recent = resumed.processFrame(scene.render(k, drifted), PoseSource::Icp);
  EXPECT_TRUE(resumed_recent.T_world_cam.isApprox(recent.T_world_cam, 0.0)) << "the resumed run tracks otherwise";
  // Against the whole model the old copy in front wins: 7.9 cm off, at the old copy's pose.
  PipelineParams whole_params = withVoxel(0.005f);
  whole_params.icp.model_window_frames = 0;
  Pipeline whole(whole_params, k, Device::Cpu);
  fuseWithDrift(whole);
  const FrameResult both = whole.processFrame(scene.render(k, drifted), PoseSource::Icp);
  EXPECT_GT((both.T_world_cam.translation() - mapped.translation()).norm(), 0.05);
}

// The window alone does not keep an old copy out where the camera comes back to it: the
// returning frame's marking lists the old bricks again, and their weight (20 frames here against
// the returning frame's one) holds the surface where it was fused long ago. With
// IcpParams::restart_stale_bricks those bricks start afresh as the returning frame fuses, and the
// next frame tracks against what that frame saw. Here a room corner is fused 20 times, then 4
// frames see nothing (the camera looks elsewhere for longer than the window of 3), then one frame
// comes back 1.5 cm further off while claiming the first pose (the drift), then one is tracked.
// A drift within the truncation band, as a walk's return brings (a larger one lands in other
// bricks, which the window keeps out by itself).
TEST(Tracking, ComingBackAfterTheModelWindowRestartsTheOldCopy) {
  const SyntheticScene scene = roomCorner();
  const Intrinsics k = testCamera(160, 120);
  const Pose mapped = Pose::Identity();
  const Pose drifted = poseFrom(0, 0, 0, 0, 0, -0.015);
  auto comeBack = [&](Pipeline& pipeline) {
    FrameResult last;
    for (int i = 0; i < 25; ++i)
      last = fuseClaimingPose(pipeline, scene, k, i < 24 ? mapped : drifted, mapped, /*blank=*/i >= 20 && i < 24);
    return last;
  };
  PipelineParams restarting = withVoxel(0.005f);
  restarting.icp.model_window_frames = 3;
  restarting.icp.restart_stale_bricks = true;
  Pipeline restarted(restarting, k, Device::Cpu);
  const FrameResult back = comeBack(restarted);
  EXPECT_GT(back.bricks_restarted, 100);
  EXPECT_LE(back.bricks_restarted, back.bricks_fused);
  EXPECT_EQ(restarted.state().bricks_restarted, back.bricks_restarted);
  const FrameResult recent = restarted.processFrame(scene.render(k, drifted), PoseSource::Icp);
  ASSERT_TRUE(recent.tracked) << recent.lost_reason;
  const double restarted_off = (recent.T_world_cam.translation() - mapped.translation()).norm();
  EXPECT_LT(restarted_off, 0.004);

  // Without the restart the old copy, 20 frames to one, holds the surface: the drift comes back.
  PipelineParams keeping = restarting;
  keeping.icp.restart_stale_bricks = false;
  Pipeline kept(keeping, k, Device::Cpu);
  EXPECT_EQ(comeBack(kept).bricks_restarted, 0);
  EXPECT_EQ(kept.state().bricks_restarted, 0);
  const FrameResult pulled = kept.processFrame(scene.render(k, drifted), PoseSource::Icp);
  const double kept_off = (pulled.T_world_cam.translation() - mapped.translation()).norm();
  EXPECT_GT(kept_off, 0.01);  // 0.9 mm restarted, 15.7 mm kept (2026-12-07)
}

TEST(Tracking, AFrameWithNoDepthIsReportedLostAndKeepsTheLastPose) {
  const SyntheticScene scene = roomCorner();
  const Intrinsics k = testCamera(160, 120);
  Pipeline pipeline(withVoxel(2.5f / 128), k, Device::Cpu);
  pipeline.processFrame(scene.render(k, Pose::Identity()));
  RgbdFrame empty = scene.render(k, Pose::Identity());
  std::fill(empty.depth.data(), empty.depth.data() + k.width * k.height, 0.f);
  const FrameResult r = pipeline.processFrame(empty);
  EXPECT_FALSE(r.tracked);
  EXPECT_FALSE(r.integrated);
  EXPECT_EQ(pipeline.framesLost(), 1);
  EXPECT_TRUE(r.T_world_cam.isApprox(Pose::Identity()));
}

TEST(Tracking, AWildJumpIsRejectedAsTrackingLoss) {
  const SyntheticScene scene = roomCorner();
  const Intrinsics k = testCamera(160, 120);
  Pipeline pipeline(withVoxel(2.5f / 128), k, Device::Cpu);
  pipeline.processFrame(scene.render(k, Pose::Identity()));
  // A view from 60 deg and 0.9 m to the side, taken as a small motion: ICP cannot explain it.
  // The solve settles where 26 % of the pixels match (more than min_inlier_fraction), but 94 %
  // lie over the model and only 28 % of those match it (IcpParams::min_covered_match).
  const FrameResult r = pipeline.processFrame(scene.render(k, poseFrom(0, 60, 0, 0.8, 0, 0.5)));
  EXPECT_FALSE(r.tracked);
  EXPECT_FALSE(r.lost_reason.empty());
}

// The CPU reduces ICP rows eight pixels at a time (IcpKernel::rows): over a count that is no
// multiple of eight, and short of the kernel's own count, it must give the sum of the rows one
// pixel at a time, within float rounding, and the counts exactly.
TEST(Tracking, TheEightLaneIcpReductionSumsTheSameRowsAsOnePixelAtATime) {
  const Intrinsics k = testCamera();
  const int n = 3 * 4096 + 77;
  const test::IcpRowsFixture data = test::makeIcpRowsFixture(k, n);
  IcpKernel icp;
  icp.vertex_cam = {data.vertex.data(), n, 1};
  icp.normal_cam = {data.normal.data(), n, 1};
  icp.model_vertex = {data.model_vertex.data(), k.width, k.height};
  icp.model_normal = {data.model_normal.data(), k.width, k.height};
  icp.model_intrinsics = k;
  icp.T_world_cam = toRigid3f(poseFrom(0.3, -0.2, 0.1, 0.002, -0.001, 0.003));
  icp.T_model_world = Rigid3f::identity();
  for (const int count : {n, 1001}) {
    SCOPED_TRACE(count);
    std::array<double, normal_row::kSize> exact{}, magnitude{};
    float row[normal_row::kSize];
    for (int i = 0; i < count; ++i) {
      if (!icp(i, row)) continue;
      for (int c = 0; c < normal_row::kSize; ++c) exact[size_t(c)] += row[c], magnitude[size_t(c)] += std::abs(row[c]);
    }
    ASSERT_GT(exact[normal_row::kInliers], 0.5 * count) << "too few correspondences for a meaningful test";
    const std::array<double, normal_row::kSize> lanes = parallelReduce<normal_row::kSize>(Device::Cpu, count, icp);
    for (int c = 0; c < normal_row::kSize; ++c)
      EXPECT_NEAR(lanes[size_t(c)], exact[size_t(c)], 1e-5 * magnitude[size_t(c)] + 1e-9) << "component " << c;
    EXPECT_EQ(lanes[normal_row::kInliers], exact[normal_row::kInliers]);
    EXPECT_EQ(lanes[normal_row::kMeasured], exact[normal_row::kMeasured]);
  }
}

// The CPU's stage times (the GPU's are events: cuda_memory_test): every stage in the order it
// first ran, one sample per run, at least as long as the work; a copy keeps the samples.
TEST(StageTimer, CpuStagesAreTimedInTheOrderTheyRanAndACopyKeepsTheSamples) {
  StageTimer timer;
  for (int i = 0; i < 3; ++i) {
    { ScopedStage measure(timer, "measure"); std::this_thread::sleep_for(std::chrono::milliseconds(2)); }
    { ScopedStage track(timer, "track", Device::Cpu); }
  }
  EXPECT_EQ(timer.stages(), (std::vector<std::string>{"measure", "track"}));
  ASSERT_EQ(timer.samples("measure").size(), 3u);
  ASSERT_EQ(timer.samples("track").size(), 3u);
  for (double ms : timer.samples("measure")) EXPECT_GE(ms, 2.0);
  EXPECT_GE(timer.median("measure"), 2.0);
  EXPECT_NEAR(timer.total("measure"), 3 * timer.mean("measure"), 1e-9);
  const StageTimer copy = timer;
  EXPECT_EQ(copy.samples("measure"), timer.samples("measure"));
  StageTimer assigned;
  assigned = timer;
  EXPECT_EQ(assigned.stages(), timer.stages());
  EXPECT_EQ(assigned.samples("track"), timer.samples("track"));
}

TEST(Volume, BricksAreAllocatedOnlyAlongTheObservedSurface) {
  SyntheticScene plane;
  plane.planes.push_back({Eigen::Vector3d(0, 0, -1), -0.5});
  const Intrinsics k = testCamera(160, 120);
  Pipeline pipeline(withVoxel(1.0f / 128), k, Device::Cpu);
  pipeline.processFrame(plane.render(k, Pose::Identity()));
  const BrickLookup v(pipeline.hostVolume());
  // The plane seen is 0.625 x 0.47 m at 0.5 m: 10 x 8 bricks of 6.25 cm across, a band of at
  // most 4 bricks deep around z = 0.5 m (brick layers 6 to 9: the truncation and the marking margin).
  EXPECT_GT(v.brickCount(), 10u * 8u);
  EXPECT_LE(v.brickCount(), 12u * 10u * 4u);
  for (size_t n = 0; n < v.brickCount(); ++n) {
    const Vec3i b = v.view().coords[n];
    EXPECT_GE(b.z, 6) << "a brick far in front of the plane";
    EXPECT_LE(b.z, 9) << "a brick far behind the plane";
  }
  EXPECT_EQ(pipeline.brickCount(), int(v.brickCount()));
}

// How the bricks one frame lists meet its band voxels: the voxels the integration updates
// within the truncation band (|sdf| < truncation), found voxel by voxel with its own rule.
struct BandCover {
  size_t band_voxels = 0;
  size_t missing = 0;           // band voxels in a brick that was never listed: holes in the surface
  size_t bricks = 0;
  size_t bricks_with_band = 0;  // listed bricks holding at least one band voxel
};

BandCover bandCoverOfOneFrame(const RgbdFrame& frame, const Pose& pose, const Intrinsics& k, PipelineParams params) {
  params.integration.integrate_filtered_depth = false;  // the fused depth is the frame's own
  const float trunc = params.volume.truncationOrDefault(), voxel = params.volume.voxel_size_m;
  const float min_d = params.measurement.min_depth_m, max_d = params.measurement.max_depth_m;
  RgbdFrame given = frame;
  given.T_world_cam_given = pose;
  Pipeline pipeline(params, k, Device::Cpu);
  pipeline.processFrame(given, PoseSource::Given);
  const BrickLookup v(pipeline.hostVolume());
  const Rigid3f T_cam_world = toRigid3f(pose.inverse()), T_world_cam = toRigid3f(pose);
  // Every voxel whose centre can reach the band: the box of all band ends, two voxels wider.
  Vec3i lo{1 << 30, 1 << 30, 1 << 30}, hi{-(1 << 30), -(1 << 30), -(1 << 30)};
  for (int y = 0; y < k.height; ++y)
    for (int x = 0; x < k.width; ++x) {
      const float d = frame.depth(x, y);
      if (!(d >= min_d && d <= max_d)) continue;
      for (float z : {d - trunc, d + trunc}) {
        const Vec3f p = (T_world_cam * k.backProject(float(x), float(y), z)) * (1.f / voxel);
        lo = {std::min(lo.x, int(std::floor(p.x)) - 2), std::min(lo.y, int(std::floor(p.y)) - 2),
              std::min(lo.z, int(std::floor(p.z)) - 2)};
        hi = {std::max(hi.x, int(std::ceil(p.x)) + 2), std::max(hi.y, int(std::ceil(p.y)) + 2),
              std::max(hi.z, int(std::ceil(p.z)) + 2)};
      }
    }
  BandCover cover;
  std::set<std::tuple<int, int, int>> band_bricks;
  for (int z = lo.z; z <= hi.z; ++z)
    for (int y = lo.y; y <= hi.y; ++y)
      for (int x = lo.x; x <= hi.x; ++x) {
        // IntegrateKernel::updateVoxel's test, to the letter.
        const Vec3f p = T_cam_world * v.voxelCenter(x, y, z);
        if (p.z <= 0.f) continue;
        float u, w;
        k.projectAnyDepth(p, u, w);
        if (!(u >= -0.5f && w >= -0.5f && u < float(k.width) - 0.5f && w < float(k.height) - 0.5f)) continue;
        const float d = frame.depth(int(std::floor(u + 0.5f)), int(std::floor(w + 0.5f)));
        if (!(d >= min_d && d <= max_d)) continue;
        const float sdf = d - p.z;
        if (sdf < -trunc || sdf >= trunc) continue;
        ++cover.band_voxels;
        const Vec3i b = brickOfVoxel(x, y, z);
        band_bricks.insert({b.x, b.y, b.z});
        if (!v.hasBrick(b)) ++cover.missing;
      }
  cover.bricks = v.brickCount();
  for (size_t n = 0; n < v.brickCount(); ++n) {
    const Vec3i b = v.view().coords[n];
    cover.bricks_with_band += band_bricks.count({b.x, b.y, b.z});
  }
  return cover;
}

TEST(Volume, MarkingListsEveryBrickWithABandVoxelAndFewOthers) {
  // From oblique poses onto the room corner's balls (depth edges) and planes, on an odd-sized
  // image (pixel blocks cut at its edges).
  const SyntheticScene scene = roomCorner();
  const Intrinsics k = testCamera(161, 121);
  BandCover total;
  for (const Pose& pose : {poseFrom(0, 0, 0, 0, 0, 0), poseFrom(12, -25, 8, 0.2, -0.1, 0.15),
                           poseFrom(-20, 35, -5, -0.1, 0.05, 0.3)}) {
    const BandCover c = bandCoverOfOneFrame(scene.render(k, pose), pose, k, withVoxel(0.01f));
    total.band_voxels += c.band_voxels, total.missing += c.missing;
    total.bricks += c.bricks, total.bricks_with_band += c.bricks_with_band;
  }
  EXPECT_GT(total.band_voxels, 500000u);
  EXPECT_EQ(total.missing, 0u) << "band voxels in bricks that were never listed";
  // A cover, not exact: a piece's box also reaches some bricks beside the band. The marking
  // before (a cube around each step of one pixel in four) listed 5623 bricks, half of them
  // (2794) holding a band voxel; this one 3388.
  EXPECT_GT(double(total.bricks_with_band), 0.8 * double(total.bricks))
      << total.bricks_with_band << " of " << total.bricks;
}

TEST(Volume, DepthOnlyInPixelsTheMarkingStridesOverIsStillFused) {
  // Depth in every other pixel only (odd rows and columns), as from a sparse sensor or a thin
  // object one pixel wide: the marking visits the block, not its first pixel, so every one of
  // those pixels still gets its band. The marking before listed no brick at all here.
  const SyntheticScene scene = roomCorner();
  const Intrinsics k = testCamera(160, 120);
  const Pose pose = poseFrom(10, -15, 0, 0.05, 0, 0.1);
  RgbdFrame frame = scene.render(k, pose);
  for (int y = 0; y < k.height; ++y)
    for (int x = 0; x < k.width; ++x)
      if (x % 2 == 0 || y % 2 == 0) frame.depth(x, y) = 0.f;
  const BandCover c = bandCoverOfOneFrame(frame, pose, k, withVoxel(0.01f));
  EXPECT_GT(c.band_voxels, 40000u);
  EXPECT_EQ(c.missing, 0u) << "band voxels in bricks that were never listed";
}

TEST(Volume, TheSameFramesGiveTheSameVoxelsWhateverTheThreadCountOrHashSize) {
  // Bricks land in the hash and the pool in the order threads reach them; the voxels must not
  // depend on it. A pipeline on one thread against one on all, each camera looking from an offset
  // so that some bricks have negative coordinates.
  const SyntheticScene scene = roomCorner();
  const Intrinsics k = testCamera(160, 120);
  auto fuse = [&](int threads) {
    tbb::global_control limit(tbb::global_control::max_allowed_parallelism, size_t(threads));
    auto pipeline = std::make_unique<Pipeline>(withVoxel(0.01f), k, Device::Cpu);
    for (int i = 0; i < 4; ++i) pipeline->processFrame(scene.render(k, poseFrom(0, 3.0 * i, 0, 0.02 * i, 0, 0)));
    return pipeline;
  };
  auto serial = fuse(1);
  auto parallel = fuse(8);
  EXPECT_EQ(serial->framesLost(), 0);
  EXPECT_TRUE(serial->pose().isApprox(parallel->pose(), 0.0));
  const BrickLookup a(serial->hostVolume()), b(parallel->hostVolume());
  EXPECT_GT(a.brickCount(), 500u);
  expectSameVoxels(a, b);
}

TEST(Volume, AFullPoolStopsAllocatingAndSaysSo) {
  SyntheticScene plane;
  plane.planes.push_back({Eigen::Vector3d(0, 0, -1), -0.5});
  const Intrinsics k = testCamera(160, 120);
  PipelineParams params = withVoxel(1.0f / 128);
  params.volume.max_bricks = 50;
  Pipeline pipeline(params, k, Device::Cpu);
  const FrameResult r = pipeline.processFrame(plane.render(k, Pose::Identity()));
  EXPECT_TRUE(r.volume_full);
  EXPECT_EQ(pipeline.brickCount(), 50);
}

TEST(Volume, ParametersThatCannotWorkAreRefusedNamingTheField) {
  const Intrinsics k = testCamera(160, 120);
  PipelineParams p = withVoxel(0.f);
  EXPECT_NE(test::errorOf([&] { Pipeline(p, k, Device::Cpu); }).find("VolumeSpec.voxel_size_m = 0"), std::string::npos);
  p = withVoxel(1e-9f);
  EXPECT_NE(test::errorOf([&] { Pipeline(p, k, Device::Cpu); }).find("VolumeSpec.voxel_size_m"), std::string::npos);
  p = withVoxel(0.01f);
  p.volume.truncation_m = 1e9f;
  EXPECT_NE(test::errorOf([&] { Pipeline(p, k, Device::Cpu); }).find("VolumeSpec.truncation_m"), std::string::npos);
  p = withVoxel(0.01f);
  Intrinsics wild = k;
  wild.cx = 1e9f;
  EXPECT_NE(test::errorOf([&] { Pipeline(p, wild, Device::Cpu); }).find("Intrinsics.cx"), std::string::npos);
}

TEST(Volume, DepthBeyondTheMaximumRangeIsNeitherMarkedNorFused) {
  // Readings of a million metres (a broken sensor), infinity and NaN must cost nothing: no brick,
  // no endless walk along the ray. A reading within range does add its band.
  SyntheticScene plane;
  plane.planes.push_back({Eigen::Vector3d(0, 0, -1), -0.5});
  const Intrinsics k = testCamera(160, 120);
  const RgbdFrame clean = plane.render(k, Pose::Identity());
  auto bricksAfter = [&](const std::function<void(RgbdFrame&)>& damage) {
    Pipeline pipeline(withVoxel(1.0f / 128), k, Device::Cpu);
    RgbdFrame frame = clean;
    damage(frame);
    pipeline.processFrame(frame);
    return pipeline.brickCount();
  };
  const int reference = bricksAfter([](RgbdFrame&) {});
  const int absurd = bricksAfter([](RgbdFrame& f) {
    f.depth(80, 60) = 1.0e6f;
    f.depth(82, 60) = std::numeric_limits<float>::infinity();
    f.depth(84, 60) = std::numeric_limits<float>::quiet_NaN();
    f.depth(86, 60) = -3.f;
  });
  const int far_but_valid = bricksAfter([](RgbdFrame& f) { f.depth(10, 10) = 3.9f; });
  EXPECT_EQ(absurd, reference);
  EXPECT_GT(far_but_valid, reference);
}

TEST(Volume, ARunReplayedAtItsOwnTrackedPosesFusesTheSameVoxels) {
  // tests/cuda compares a CUDA run with ICP against the CPU fusing the same frames at the poses
  // that run tracked: fusion must depend on the frames and the poses alone, not on how they came.
  const SyntheticScene scene = roomCorner();
  const Intrinsics k = testCamera(160, 120);
  Pipeline tracked(withVoxel(0.01f), k, Device::Cpu);
  Pipeline replayed(withVoxel(0.01f), k, Device::Cpu);
  for (int i = 0; i < 6; ++i) {
    RgbdFrame frame = scene.render(k, poseFrom(0.5 * i, -0.8 * i, 0.3 * i, 0.01 * i, -0.005 * i, 0.006 * i));
    const FrameResult r = tracked.processFrame(frame, PoseSource::Icp);
    ASSERT_TRUE(r.tracked) << "frame " << i << ": " << r.lost_reason;
    frame.T_world_cam_given = r.T_world_cam;
    replayed.processFrame(frame, PoseSource::Given);
  }
  const BrickLookup a(tracked.hostVolume()), b(replayed.hostVolume());
  EXPECT_GT(a.brickCount(), 500u);
  expectSameVoxels(a, b);
}

TEST(Volume, ChunkCullingKeepsEveryBrickTheRaycastWouldProjectAndSkipsTheRest) {
  // BrickChunks must be exact: every brick whose own sphere BrickRangeKernel keeps is listed,
  // whatever the pose; bricks far out of view are not, which is what it is for.
  std::mt19937 random(5);
  std::uniform_int_distribution<int> coord(-60, 60);
  std::vector<Vec3i> bricks(20000);
  for (Vec3i& b : bricks) b = {coord(random), coord(random), coord(random)};
  BrickChunks chunks;
  chunks.add(bricks.data(), 0, int(bricks.size()));
  const Intrinsics k = testCamera(320, 240);
  const float voxel_m = 0.00586f, edge_m = kBrickSize * voxel_m;
  const FrustumCull cull = FrustumCull::make(k, 0.2f, 4.f);
  std::vector<int> listed;
  size_t kept_total = 0, listed_total = 0;
  for (int pose = 0; pose < 20; ++pose) {
    const Rigid3f T_cam_world = toRigid3f(poseFrom(17.0 * pose, 31.0 * pose, 7.0 * pose, 0.1 * pose, -0.05 * pose, 0.02));
    chunks.gatherVisible(cull, T_cam_world, edge_m, listed);
    std::vector<char> is_listed(bricks.size(), 0);
    for (int slot : listed) is_listed[size_t(slot)] = 1;
    for (size_t slot = 0; slot < bricks.size(); ++slot) {
      const Vec3i b = bricks[slot];
      const Vec3f center = T_cam_world * (Vec3f{float(b.x), float(b.y), float(b.z)} * edge_m + Vec3f{0.5f, 0.5f, 0.5f} * edge_m);
      if (cull.outside(center, 0.8661f * edge_m)) continue;
      ++kept_total;
      EXPECT_TRUE(is_listed[slot]) << "pose " << pose << ": brick " << b.x << "," << b.y << "," << b.z << " dropped";
    }
    listed_total += listed.size();
  }
  EXPECT_GT(kept_total, 1000u);
  EXPECT_LT(listed_total, 20 * bricks.size() / 2) << "the chunks culled less than half of the bricks";
}

}  // namespace
}  // namespace vf
