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

// A camera's walk fed to a RecentMotion frame by frame: T and t are where and when it is now.
struct Walker {
  explicit Walker(double start_s = 0) : t(start_s) { motion.add(T, t, false); }
  // `frames` frames kFrameS apart, each following the one before.
  void walk(int frames, double speed_m_s, double turn_deg_s) {
    for (int i = 0; i < frames; ++i) motion.add(T = T * walkStep(speed_m_s, turn_deg_s, kFrameS), t += kFrameS, true);
  }
  RecentMotion motion;
  Pose T = Pose::Identity();
  double t;
};

double metresApart(const Pose& a, const Pose& b) { return (a.translation() - b.translation()).norm(); }
double degreesApart(const Pose& a, const Pose& b) {
  return Eigen::AngleAxisd((a.inverse() * b).linear()).angle() * 180.0 / M_PI;
}

TEST(RecentMotion, ALostCameraGoesOnAtItsSteadyPaceNotAtItsLastFramesSlide) {
  Walker w;
  w.walk(30, 1.0, 10.0);
  // The last eight frames slide backwards along the corridor, faster each frame (the ring
  // corridor's return: 33 mm a frame forward became 98 mm a frame back).
  for (int i = 1; i <= 8; ++i) w.walk(1, -0.4 * i, 10.0);
  const Pose guess = w.motion.extrapolate(w.t + 0.4, 2.0);
  const Pose steady = w.T * walkStep(1.0, 10.0, 0.4);
  EXPECT_LT(metresApart(guess, steady), 1e-9);
  EXPECT_LT(degreesApart(guess, steady), 1e-9);
  // The last step carried on (3.2 m/s backwards) would have put it 1.68 m behind.
  EXPECT_GT(metresApart(w.T * walkStep(-3.2, 10.0, 0.4), steady), 1.6);
}

TEST(RecentMotion, OnlyTheLastSecondCountsAndNoFasterThanTheCameraCanMove) {
  Walker w;
  w.walk(60, 1.8, 0.0);
  w.walk(31, 0.5, 0.0);
  EXPECT_NEAR(metresApart(w.motion.extrapolate(w.t + 1.0, 2.0), w.T), 0.5, 1e-9);
  // A camera that was running: at most max_speed_m_s.
  w.walk(31, 3.0, 0.0);
  EXPECT_NEAR(metresApart(w.motion.extrapolate(w.t + 0.5, 2.0), w.T), 1.0, 1e-9);
}

TEST(RecentMotion, TheWalkGoesOnAtItsPaceTheTurnAsInTheLastStep) {
  Walker w;
  w.walk(29, 1.0, 35.0);
  w.walk(1, 1.0, 0.0);  // round the corner
  const Pose guess = w.motion.extrapolate(w.t + 1.9, 2.0);
  EXPECT_LT(degreesApart(guess, w.T), 1e-9);
  EXPECT_NEAR(metresApart(guess, w.T), 1.9, 1e-9);
  EXPECT_GT((w.T.inverse() * guess).translation().z(), 1.89);  // straight on
  w.walk(1, 1.0, -20.0);  // and turning back
  EXPECT_NEAR(degreesApart(w.motion.extrapolate(w.t + 0.5, 2.0), w.T), 10.0, 1e-6);
}

TEST(RecentMotion, AFrameThatDoesNotFollowStartsAfresh) {
  Walker w;
  w.walk(10, 1.0, 0.0);
  EXPECT_GT(metresApart(w.motion.extrapolate(w.t + 0.3, 2.0), w.T), 0.29);
  // Relocalised after a gap: no motion known yet, the guess is where it was found.
  w.motion.add(w.T = w.T * walkStep(1.0, 30.0, 1.0), w.t += 1.0, false);
  EXPECT_EQ(w.motion.extrapolate(w.t + 0.3, 2.0).matrix(), w.T.matrix());
  EXPECT_EQ(RecentMotion().extrapolate(1.0, 2.0).matrix(), Pose::Identity().matrix());
}

TEST(RecentMotion, ACheckpointKeepsItAndABadOneIsRefused) {
  Walker w(5.0);
  w.walk(12, 0.7, 20.0);
  std::vector<uint8_t> bytes;
  ByteWriter writer(bytes);
  w.motion.write(writer);
  RecentMotion back;
  ByteReader in(bytes.data(), bytes.size(), "test checkpoint");
  back.read(in);
  EXPECT_EQ(back.extrapolate(w.t + 0.5, 2.0).matrix(), w.motion.extrapolate(w.t + 0.5, 2.0).matrix());

  std::vector<uint8_t> shuffled = bytes;  // the first two samples' times swapped
  std::swap_ranges(shuffled.begin() + 4, shuffled.begin() + 12, shuffled.begin() + 4 + 136);
  ByteReader bad(shuffled.data(), shuffled.size(), "test checkpoint");
  EXPECT_THROW(back.read(bad), Error);
}

}  // namespace
}  // namespace vf::slam
