// Numbers the fusion stages must reproduce on analytic scenes with known answers.
#include <gtest/gtest.h>

#include "fusion/pipeline.h"
#include "fusion/volume_sampling.h"
#include "synthetic_scene.h"

namespace vf {
namespace {

using test::poseFrom;
using test::roomCorner;
using test::SyntheticScene;
using test::testCamera;

PipelineParams smallVolume(int dim, float extent_m) {
  PipelineParams p;
  p.volume.dims = {dim, dim, dim};
  p.volume.voxel_size_m = extent_m / float(dim);
  return p;
}

// Normalised TSDF along the voxel column through (x, y), interpolated to the zero crossing.
double zeroCrossingZ(const VolumeView& v, int x, int y) {
  for (int z = 0; z + 1 < v.dims.z; ++z) {
    const size_t a = v.voxelIndex(x, y, z), b = v.voxelIndex(x, y, z + 1);
    if (v.tsdf[a].weight == 0 || v.tsdf[b].weight == 0) continue;
    const double sa = v.tsdf[a].tsdf, sb = v.tsdf[b].tsdf;
    if (sa > 0 && sb <= 0) {
      const double t = sa / (sa - sb);
      return v.voxelCenter(x, y, z).z + t * v.voxel_size_m;
    }
  }
  return NAN;
}

TEST(Integration, PlaneAtHalfMetreHasItsZeroCrossingThereWithinHalfAVoxel) {
  SyntheticScene plane;
  plane.planes.push_back({Eigen::Vector3d(0, 0, -1), -0.5});  // z = 0.5 m
  const Intrinsics k = testCamera();
  PipelineParams params = smallVolume(128, 1.0f);
  Pipeline pipeline(params, k, Device::Cpu);
  for (int i = 0; i < 3; ++i) pipeline.processFrame(plane.render(k, Pose::Identity()));
  const VolumeView& v = pipeline.hostVolume().view();
  int checked = 0;
  for (int y = 40; y < 90; y += 7)
    for (int x = 40; x < 90; x += 7) {
      const double z = zeroCrossingZ(v, x, y);
      ASSERT_TRUE(std::isfinite(z)) << "no zero crossing in column " << x << "," << y;
      EXPECT_NEAR(z, 0.5, 0.5 * v.voxel_size_m);
      ++checked;
    }
  EXPECT_GT(checked, 40);
  EXPECT_EQ(pipeline.framesLost(), 0);
}

TEST(Raycast, FusedSphereIsFoundAtItsRadiusWithinOneVoxel) {
  SyntheticScene scene;
  const Eigen::Vector3d center(0.05, -0.03, 0.9);
  const double radius = 0.25;
  scene.spheres.push_back({center, radius});
  const Intrinsics k = testCamera();
  Pipeline pipeline(smallVolume(256, 2.0f), k, Device::Cpu);
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
  PipelineParams params = smallVolume(256, 2.5f);
  params.place_like_kinectfusion = false;
  params.volume.origin_m = {-1.25f, -1.0f, 0.2f};
  Pipeline pipeline(params, k, Device::Cpu);
  const Pose truth = poseFrom(1.2, -1.5, 0.8, 0.015, -0.01, 0.02);
  pipeline.processFrame(scene.render(k, Pose::Identity()));
  const FrameResult r = pipeline.processFrame(scene.render(k, truth));
  ASSERT_TRUE(r.tracked) << r.lost_reason;
  const Pose error = truth.inverse() * r.T_world_cam;
  EXPECT_LT(error.translation().norm(), 1e-3);
  EXPECT_LT(Eigen::AngleAxisd(error.linear()).angle() * 180 / M_PI, 0.1);
}

TEST(Tracking, AFrameWithNoDepthIsReportedLostAndKeepsTheLastPose) {
  const SyntheticScene scene = roomCorner();
  const Intrinsics k = testCamera(160, 120);
  Pipeline pipeline(smallVolume(128, 2.5f), k, Device::Cpu);
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
  Pipeline pipeline(smallVolume(128, 2.5f), k, Device::Cpu);
  pipeline.processFrame(scene.render(k, Pose::Identity()));
  // A view from far to the side: little overlap, ICP cannot explain it.
  const FrameResult r = pipeline.processFrame(scene.render(k, poseFrom(0, 60, 0, 0.8, 0, 0.5)));
  EXPECT_FALSE(r.tracked);
  EXPECT_FALSE(r.lost_reason.empty());
}

TEST(Volume, UntouchedBricksStayUnobserved) {
  SyntheticScene plane;
  plane.planes.push_back({Eigen::Vector3d(0, 0, -1), -0.5});
  const Intrinsics k = testCamera(160, 120);
  Pipeline pipeline(smallVolume(128, 1.0f), k, Device::Cpu);
  pipeline.processFrame(plane.render(k, Pose::Identity()));
  const DenseVolume& vol = pipeline.hostVolume();
  const auto bricks = vol.observedBricks();
  // A plane of about 1 m x 0.75 m at 7.8 mm voxels touches a thin slab of bricks, not the volume.
  EXPECT_GT(bricks.size(), 100u);
  EXPECT_LT(bricks.size(), size_t(vol.view().brickCount()) / 8);
}

}  // namespace
}  // namespace vf
