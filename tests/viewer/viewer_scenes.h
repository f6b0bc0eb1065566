#pragma once
// Small scenes for the viewer tests: a ball resting above a floor, two classes split at x = 0
// (fused colors red / green from vdb/synthetic_scene.h, class colors yellow / cyan so that the
// two colorings differ everywhere), and a short trajectory beside the file.
#include <cmath>
#include <string>

#include "io/trajectory_io.h"
#include "vdb/scene.h"
#include "vdb/synthetic_scene.h"

namespace vf::test {

constexpr float kBallRadius = 0.18f;
constexpr float kFloorY = 0.22f;  // y points down (camera frame): the floor is at +y
constexpr Rgb8 kChairColor{230, 200, 40, 255}, kTableColor{40, 200, 220, 255};

inline Scene ballOnFloorScene(bool with_classes) {
  test::SyntheticVolume volume(sphereSpec(64, 0.01f), with_classes);
  const auto ball = sphereSdf({0, 0, 0}, kBallRadius);
  fillSdf(volume, [&](Vec3f p) { return std::min(ball(p), kFloorY - p.y); }, 0.f);
  SceneMetadata meta;
  if (with_classes) meta.classes.classes = {{kClassLeft, "chair", kChairColor}, {kClassRight, "table", kTableColor}};
  meta.source = "viewer test ball";
  meta.up_world = {0, -1, 0};  // as reconstruct records it: up and heading of the first camera
  meta.forward_world = {0, 0, 1};
  meta.up_source = "camera up-vectors";
  return sceneFromBricks(volume.view(), meta);
}

// A rotation of the world: tilt_deg about x, then turn_deg about z.
inline Eigen::Matrix3d tiltRotation(double tilt_deg, double turn_deg) {
  return (Eigen::AngleAxisd(turn_deg * M_PI / 180, Eigen::Vector3d::UnitZ()) *
          Eigen::AngleAxisd(tilt_deg * M_PI / 180, Eigen::Vector3d::UnitX()))
      .toRotationMatrix();
}
inline Vec3f rotated(const Eigen::Matrix3d& r, Vec3f v) {
  const Eigen::Vector3d w = r * Eigen::Vector3d(v.x, v.y, v.z);
  return {float(w.x()), float(w.y()), float(w.z())};
}

// The ball on its floor, both turned by tiltRotation (the world frame of a first camera that
// looked down and rolled, or of recorded poses): the floor's normal is the recorded up.
inline Scene tiltedBallOnFloorScene(double tilt_deg, double turn_deg) {
  const Eigen::Matrix3d r = tiltRotation(tilt_deg, turn_deg);
  const Vec3f up = rotated(r, {0, -1, 0}), forward = rotated(r, {0, 0, 1});
  test::SyntheticVolume volume(sphereSpec(64, 0.01f), false);
  const auto ball = sphereSdf({0, 0, 0}, kBallRadius);
  fillSdf(volume, [&](Vec3f p) { return std::min(ball(p), dot(p, up) + kFloorY); }, 0.f);
  SceneMetadata meta;
  meta.source = "viewer test tilted ball";
  meta.up_world = up;
  meta.forward_world = forward;
  meta.up_source = "recorded poses";
  return sceneFromBricks(volume.view(), meta);
}

// Ten cameras on a short arc in front of the ball, looking at it (+z forward, y down).
inline Trajectory arcTrajectory() {
  Trajectory t;
  for (int i = 0; i < 10; ++i) {
    const double a = (i - 4.5) * 0.06;
    StampedPose p;
    p.timestamp = 100.0 + 0.1 * i;
    p.T_world_cam.linear() = Eigen::AngleAxisd(-a, Eigen::Vector3d::UnitY()).toRotationMatrix();
    p.T_world_cam.translation() = Eigen::Vector3d(0.6 * std::sin(a), -0.05, -0.6 * std::cos(a));
    t.push_back(p);
  }
  return t;
}

// Writes <dir>/<stem>.vdb (and <stem>.txt with the arc trajectory); returns the .vdb path.
inline std::string writeBallScene(const std::string& dir, const std::string& stem, bool with_classes,
                                  bool with_trajectory) {
  const std::string path = dir + "/" + stem + ".vdb";
  writeScene(ballOnFloorScene(with_classes), path);
  if (with_trajectory) writeTumTrajectory(dir + "/" + stem + ".txt", arcTrajectory());
  return path;
}

}  // namespace vf::test
