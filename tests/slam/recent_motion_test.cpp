// Where a lost camera has most likely got to (slam/recent_motion.h): the walk's steady pace
// carried on, whatever its last few frames did, turning as in its last step.
#include <gtest/gtest.h>

#include <cmath>

#include "slam/recent_motion.h"

namespace vf::slam {
namespace {

constexpr double kFrameS = 1.0 / 30.0;

// Walking forward (+z) at speed_m_s while turning about the camera's y at turn_deg_s.
Pose walkStep(double speed_m_s, double turn_deg_s, double dt) {
  Pose step = Pose::Identity();
  step.linear() = Eigen::AngleAxisd(turn_deg_s * dt * M_PI / 180.0, Eigen::Vector3d::UnitY()).toRotationMatrix();
  step.translation() = Eigen::Vector3d(0, 0, speed_m_s * dt);
  return step;
}

double metresApart(const Pose& a, const Pose& b) { return (a.translation() - b.translation()).norm(); }
double degreesApart(const Pose& a, const Pose& b) {
  return Eigen::AngleAxisd((a.inverse() * b).linear()).angle() * 180.0 / M_PI;
}

TEST(RecentMotion, ALostCameraGoesOnAtItsSteadyPaceNotAtItsLastFramesSlide) {
  RecentMotion motion;
  Pose T = Pose::Identity();
  double t = 0;
  motion.add(T, t, false);
  for (int i = 0; i < 30; ++i) motion.add(T = T * walkStep(1.0, 10.0, kFrameS), t += kFrameS, true);
  // The last eight frames slide backwards along the corridor, faster each frame (the ring
  // corridor's return: 33 mm a frame forward became 98 mm a frame back).
  for (int i = 1; i <= 8; ++i) motion.add(T = T * walkStep(-0.4 * i, 10.0, kFrameS), t += kFrameS, true);
  const Pose guess = motion.extrapolate(t + 0.4, 2.0);
  const Pose steady = T * walkStep(1.0, 10.0, 0.4);
  EXPECT_LT(metresApart(guess, steady), 1e-9);
  EXPECT_LT(degreesApart(guess, steady), 1e-9);
  // The last step carried on (3.2 m/s backwards) would have put it 1.68 m behind.
  EXPECT_GT(metresApart(T * walkStep(-3.2, 10.0, 0.4), steady), 1.6);
}

TEST(RecentMotion, OnlyTheLastSecondCountsAndNoFasterThanTheCameraCanMove) {
  RecentMotion motion;
  Pose T = Pose::Identity();
  double t = 0;
  motion.add(T, t, false);
  for (int i = 0; i < 60; ++i) motion.add(T = T * walkStep(1.8, 0.0, kFrameS), t += kFrameS, true);
  for (int i = 0; i < 31; ++i) motion.add(T = T * walkStep(0.5, 0.0, kFrameS), t += kFrameS, true);
  EXPECT_NEAR(metresApart(motion.extrapolate(t + 1.0, 2.0), T), 0.5, 1e-9);
  // A camera that was running: at most max_speed_m_s.
  for (int i = 0; i < 31; ++i) motion.add(T = T * walkStep(3.0, 0.0, kFrameS), t += kFrameS, true);
  EXPECT_NEAR(metresApart(motion.extrapolate(t + 0.5, 2.0), T), 1.0, 1e-9);
}

TEST(RecentMotion, TheWalkGoesOnAtItsPaceTheTurnAsInTheLastStep) {
  RecentMotion motion;
  Pose T = Pose::Identity();
  double t = 0;
  motion.add(T, t, false);
  for (int i = 0; i < 29; ++i) motion.add(T = T * walkStep(1.0, 35.0, kFrameS), t += kFrameS, true);
  motion.add(T = T * walkStep(1.0, 0.0, kFrameS), t += kFrameS, true);  // round the corner
  const Pose guess = motion.extrapolate(t + 1.9, 2.0);
  EXPECT_LT(degreesApart(guess, T), 1e-9);
  EXPECT_NEAR(metresApart(guess, T), 1.9, 1e-9);
  EXPECT_GT((T.inverse() * guess).translation().z(), 1.89);  // straight on
  motion.add(T = T * walkStep(1.0, -20.0, kFrameS), t += kFrameS, true);  // and turning back
  EXPECT_NEAR(degreesApart(motion.extrapolate(t + 0.5, 2.0), T), 10.0, 1e-6);
}

TEST(RecentMotion, AFrameThatDoesNotFollowStartsAfresh) {
  RecentMotion motion;
  Pose T = Pose::Identity();
  double t = 0;
  motion.add(T, t, false);
  for (int i = 0; i < 10; ++i) motion.add(T = T * walkStep(1.0, 0.0, kFrameS), t += kFrameS, true);
  EXPECT_GT(metresApart(motion.extrapolate(t + 0.3, 2.0), T), 0.29);
  // Relocalised after a gap: no motion known yet, the guess is where it was found.
  motion.add(T = T * walkStep(1.0, 30.0, 1.0), t += 1.0, false);
  EXPECT_EQ(motion.extrapolate(t + 0.3, 2.0).matrix(), T.matrix());
  EXPECT_EQ(RecentMotion().extrapolate(1.0, 2.0).matrix(), Pose::Identity().matrix());
}

TEST(RecentMotion, ACheckpointKeepsItAndABadOneIsRefused) {
  RecentMotion motion;
  Pose T = Pose::Identity();
  double t = 5;
  motion.add(T, t, false);
  for (int i = 0; i < 12; ++i) motion.add(T = T * walkStep(0.7, 20.0, kFrameS), t += kFrameS, true);
  std::vector<uint8_t> bytes;
  ByteWriter w(bytes);
  motion.write(w);
  RecentMotion back;
  ByteReader in(bytes.data(), bytes.size(), "test checkpoint");
  back.read(in);
  EXPECT_EQ(back.extrapolate(t + 0.5, 2.0).matrix(), motion.extrapolate(t + 0.5, 2.0).matrix());

  std::vector<uint8_t> shuffled = bytes;  // the first two samples' times swapped
  std::swap_ranges(shuffled.begin() + 4, shuffled.begin() + 12, shuffled.begin() + 4 + 136);
  ByteReader bad(shuffled.data(), shuffled.size(), "test checkpoint");
  EXPECT_THROW(back.read(bad), Error);
}

}  // namespace
}  // namespace vf::slam
