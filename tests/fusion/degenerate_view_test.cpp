// A view of one flat, textureless wall constrains three of the six pose directions: moving
// towards it and tilting about the two axes in its plane. Sliding along it and turning about its
// normal change nothing the camera sees, so the solve must leave them where the motion prior puts
// them (no motion, or the last frame's motion continued) instead of moving the camera there on
// the depth noise alone (fusion/tracking.cpp). Where texture on the wall measures the slide but
// the solve stops at a photometric minimum a period short, a second solve started at the prior
// finds the walk's motion.
#include <gtest/gtest.h>

#include <random>

#include "fusion/pipeline.h"
#include "synthetic_scene.h"

namespace vf {
namespace {

using test::poseFrom;
using test::SyntheticScene;
using test::testCamera;

// One wall 0.9 m in front of the first camera, rendered without colour and with depth noise of
// 1.5 mm (a structured-light sensor at that range), the same noise for the same seed.
RgbdFrame wallFrame(const Intrinsics& k, const Pose& T_world_cam, unsigned seed) {
  SyntheticScene wall;
  wall.planes.push_back({Eigen::Vector3d(0, 0, -1), -0.9});
  RgbdFrame frame = wall.render(k, T_world_cam);
  frame.color = ColorImage();
  std::mt19937 random(seed);
  std::normal_distribution<float> noise(0.f, 0.0015f);
  for (int i = 0; i < k.width * k.height; ++i) frame.depth.data()[i] += noise(random);
  return frame;
}

// What the second camera's pose says about the wall: how far its centre slid along the wall
// (x, y: what the view cannot see), how far the wall is, and the rotation vector in degrees
// (z: about the wall's normal, unseen; x: a tilt the view sees).
struct WallView {
  Eigen::Vector2d slide;
  double distance;
  Eigen::Vector3d rotation_deg;
};

WallView wallViewOf(const Pose& T_world_cam) {
  const Eigen::AngleAxisd r(T_world_cam.linear());
  return {T_world_cam.translation().head<2>(), 0.9 - T_world_cam.translation().z(),
          r.angle() * r.axis() * 180.0 / M_PI};
}

FrameResult trackWall(float degenerate_share, const Pose& truth) {
  const Intrinsics k = testCamera(320, 240);
  PipelineParams params;
  params.volume.voxel_size_m = 0.004f;
  params.icp.degenerate_share = degenerate_share;
  Pipeline pipeline(params, k, Device::Cpu);
  pipeline.processFrame(wallFrame(k, Pose::Identity(), 1));
  return pipeline.processFrame(wallFrame(k, truth, 2));
}

TEST(DegenerateView, OneWallLeavesSlidingAndTurningAboutItsNormalAtThePrediction) {
  // Towards the wall 12 mm and tilted 0.6 degrees about x: what the view constrains; slid 10 and
  // 8 mm along it and turned 0.5 degrees about its normal: what it cannot see.
  const Pose truth = poseFrom(0.6, 0, 0.5, 0.010, 0.008, 0.012);
  const FrameResult r = trackWall(PipelineParams().icp.degenerate_share, truth);
  ASSERT_TRUE(r.tracked) << r.lost_reason;
  EXPECT_EQ(r.degenerate_directions, 3);
  const WallView v = wallViewOf(r.T_world_cam), t = wallViewOf(truth);
  // Held at the prediction (no motion): the camera centre does not slide along the wall and does
  // not turn about its normal. (The tilt the data measures turns the view about the camera
  // centre, so the wall point the first camera looked at leaves the image centre by 9 mm: the
  // hold is on the camera, not on what it looks at.)
  EXPECT_LT(v.slide.norm(), 5e-4) << v.slide.transpose();
  EXPECT_LT(std::abs(v.rotation_deg.z()), 0.02) << v.rotation_deg.transpose();
  // Recovered from the data: the distance to the wall and the tilt.
  EXPECT_NEAR(v.distance, t.distance, 1e-3);
  EXPECT_NEAR(v.rotation_deg.x(), t.rotation_deg.x(), 0.05) << v.rotation_deg.transpose();
}

TEST(DegenerateView, WithoutHoldingThemTheUnseenDirectionsWanderWithTheNoise) {
  // The same frames with the hold switched off: the solve moves the camera along the wall and
  // turns it about the normal (the reason for the hold; if this ever stops wandering, the test
  // above proves nothing).
  const Pose truth = poseFrom(0.6, 0, 0.5, 0.010, 0.008, 0.012);
  const WallView held = wallViewOf(trackWall(PipelineParams().icp.degenerate_share, truth).T_world_cam);
  const WallView free = wallViewOf(trackWall(0.f, truth).T_world_cam);
  EXPECT_GT(free.slide.norm(), 10 * std::max(held.slide.norm(), 1e-4))
      << "held " << held.slide.transpose() << ", free " << free.slide.transpose();
  EXPECT_GT(std::abs(free.rotation_deg.z()), 0.1) << free.rotation_deg.transpose();
}

TEST(DegenerateView, ACameraSlidingAlongTheWallKeepsItsMotionThere) {
  // Two frames with recorded poses 10 mm apart along the wall, then a third 10 mm further that
  // ICP must place: the view cannot see the slide, so the prior decides, and the prior is the
  // motion the camera had (a walk past a blank wall does not stop at its first frame).
  const Intrinsics k = testCamera(320, 240);
  PipelineParams params;
  params.volume.voxel_size_m = 0.004f;
  Pipeline pipeline(params, k, Device::Cpu);
  for (int i = 0; i < 2; ++i) {
    RgbdFrame frame = wallFrame(k, poseFrom(0, 0, 0, 0.010 * i, 0, 0), unsigned(i + 1));
    frame.T_world_cam_given = poseFrom(0, 0, 0, 0.010 * i, 0, 0);
    pipeline.processFrame(frame, PoseSource::Given);
  }
  const Pose truth = poseFrom(0, 0, 0, 0.020, 0, 0);
  const FrameResult r = pipeline.processFrame(wallFrame(k, truth, 3), PoseSource::Icp);
  ASSERT_TRUE(r.tracked) << r.lost_reason;
  EXPECT_EQ(r.degenerate_directions, 3);
  // Held at the last pose instead, it would stay at x = 10 mm.
  EXPECT_NEAR(r.T_world_cam.translation().x(), 0.020, 5e-4) << r.T_world_cam.translation().transpose();
  EXPECT_NEAR(r.T_world_cam.translation().y(), 0.0, 5e-4) << r.T_world_cam.translation().transpose();
}

// The wall with a grating on it (grey stripes 80 mm apart over 30 x 30 cm, plain grey elsewhere:
// texture only there), rendered with colour.
RgbdFrame gratingFrame(const Intrinsics& k, const Pose& T_world_cam, unsigned seed) {
  SyntheticScene wall;
  wall.planes.push_back({Eigen::Vector3d(0, 0, -1), -0.9});
  wall.color_at = [](const Eigen::Vector3d& p) {
    const bool on = std::abs(p.x()) < 0.15 && std::abs(p.y()) < 0.15;
    const auto grey = uint8_t(on ? 128 + 100 * std::sin(2 * M_PI * p.x() / 0.080) : 128);
    return Rgb8{grey, grey, grey, 255};
  };
  RgbdFrame frame = wall.render(k, T_world_cam);
  std::mt19937 random(seed);
  std::normal_distribution<float> noise(0.f, 0.0015f);
  for (int i = 0; i < k.width * k.height; ++i) frame.depth.data()[i] += noise(random);
  return frame;
}

// Recorded poses 60 mm apart along the grating (x = -60, 0, 60 mm), then a frame 60 mm further
// (x = 120) placed by ICP from the still guess, the coarsest level not started at the prior: the
// geometry leaves the slide free and the grating's nearest photometric minimum lies a period
// short of the motion (x = 40), where the prior (the last step carried on) stands right.
FrameResult placedOnTheGrating(bool second_start) {
  const Intrinsics k = testCamera(320, 240);
  PipelineParams params;
  params.volume.voxel_size_m = 0.004f;
  params.icp.degenerate_start_at_prior = false;
  params.icp.second_start_at_prior = second_start;
  Pipeline pipeline(params, k, Device::Cpu);
  for (int i = 0; i < 3; ++i) {
    const Pose T = poseFrom(0, 0, 0, -0.06 + 0.06 * i, 0, 0);
    RgbdFrame frame = gratingFrame(k, T, unsigned(i + 1));
    frame.T_world_cam_given = T;
    pipeline.processFrame(frame, PoseSource::Given);
  }
  return pipeline.processFrame(gratingFrame(k, poseFrom(0, 0, 0, 0.12, 0, 0), 4), PoseSource::Icp);
}

TEST(DegenerateView, ASolveCaughtAGratingPeriodShortIsSolvedAgainFromThePrior) {
  const FrameResult first_only = placedOnTheGrating(false), with_second = placedOnTheGrating(true);
  ASSERT_TRUE(first_only.tracked) << first_only.lost_reason;
  ASSERT_TRUE(with_second.tracked) << with_second.lost_reason;
  EXPECT_EQ(with_second.degenerate_directions, 3);
  // The first solve alone stays caught near the grating's minimum short of the motion (x = 47
  // mm when written); the second, started at the prior, fits better and is kept.
  EXPECT_LT(first_only.T_world_cam.translation().x(), 0.07);
  EXPECT_EQ(first_only.second_start_moved_m, 0.f);
  EXPECT_NEAR(with_second.T_world_cam.translation().x(), 0.12, 1e-3) << with_second.T_world_cam.translation().transpose();
  EXPECT_NEAR(with_second.second_start_moved_m, 0.12 - first_only.T_world_cam.translation().x(), 2e-3);
}

// Recorded poses along the grating whose last step overshot the walk (x = -80, -70, 10, 100 mm),
// then a frame 10 mm on (x = 110) placed by ICP. Its prior, the last step carried on, stands a
// grating period past it (x = 190); the camera's pace, 10 mm a frame, is the other start
// (TrackingCheck::pace_motion; the tracker gives its median over the last second).
FrameResult placedAfterAnOvershoot(bool start_at_pace) {
  const Intrinsics k = testCamera(320, 240);
  PipelineParams params;
  params.volume.voxel_size_m = 0.004f;
  params.icp.second_start_at_pace = start_at_pace;
  Pipeline pipeline(params, k, Device::Cpu);
  const double recorded_x[] = {-0.08, -0.07, 0.01, 0.10};
  for (int i = 0; i < 4; ++i) {
    const Pose T = poseFrom(0, 0, 0, recorded_x[i], 0, 0);
    RgbdFrame frame = gratingFrame(k, T, unsigned(i + 1));
    frame.T_world_cam_given = T;
    pipeline.processFrame(frame, PoseSource::Given);
  }
  pipeline.measure(gratingFrame(k, poseFrom(0, 0, 0, 0.11, 0, 0), 5));
  TrackingCheck check{pipeline.pose(), false};
  check.pace_motion = poseFrom(0, 0, 0, 0.01, 0, 0);
  return pipeline.track(pipeline.pose(), check);
}

TEST(DegenerateView, AnOvershotPriorIsSolvedAgainFromThePace) {
  const FrameResult prior_only = placedAfterAnOvershoot(false), with_pace = placedAfterAnOvershoot(true);
  ASSERT_TRUE(prior_only.tracked) << prior_only.lost_reason << " x " << prior_only.T_world_cam.translation().x();
  ASSERT_TRUE(with_pace.tracked) << with_pace.lost_reason;
  std::printf("held at the last step: x = %.1f mm; with the pace start: x = %.1f mm\n",
              1e3 * prior_only.T_world_cam.translation().x(), 1e3 * with_pace.T_world_cam.translation().x());
  EXPECT_GT(std::abs(prior_only.T_world_cam.translation().x() - 0.11), 0.01);
  EXPECT_FALSE(prior_only.second_start_at_pace);
  EXPECT_NEAR(with_pace.T_world_cam.translation().x(), 0.11, 1e-3) << with_pace.T_world_cam.translation().transpose();
  EXPECT_TRUE(with_pace.second_start_at_pace);
}

}  // namespace
}  // namespace vf
