// Turning a later map to face as the older ones do (slam/map_orientation.h): a room's floor,
// ceiling and walls are found among noisy normals with clutter; a map placed 13 degrees off
// (heading and tilt) is turned back within half a degree; one plane, or a turn near the
// building's 45-degree ambiguity, turns nothing.
#include <gtest/gtest.h>

#include <Eigen/Geometry>
#include <cmath>
#include <random>

#include "slam/map_orientation.h"

namespace vf::slam {
namespace {

double angleDeg(const Eigen::Matrix3d& R) { return Eigen::AngleAxisd(R).angle() * 180.0 / M_PI; }

// Normals of a box room (world z up, walls facing +-x and +-y) in these shares, each tilted by
// about 3 degrees of noise, plus a share of clutter facing anywhere.
std::vector<Eigen::Vector3d> roomNormals(size_t count, double floor_share, double wall_x_share, double clutter_share,
                                         unsigned seed) {
  std::mt19937 rng(seed);
  std::uniform_real_distribution<double> u(0.0, 1.0);
  std::normal_distribution<double> noise(0.0, 3.0 * M_PI / 180.0);
  std::vector<Eigen::Vector3d> out;
  for (size_t i = 0; i < count; ++i) {
    const double pick = u(rng);
    Eigen::Vector3d n;
    if (pick < clutter_share) {
      n = Eigen::Vector3d(noise(rng), noise(rng), noise(rng)) * 100.0;
    } else if (pick < clutter_share + floor_share) {
      n = Eigen::Vector3d::UnitZ();
    } else {
      const double side = u(rng) < 0.5 ? -1.0 : 1.0;
      n = u(rng) < wall_x_share ? Eigen::Vector3d(side, 0, 0) : Eigen::Vector3d(0, side, 0);
    }
    if (pick >= clutter_share) n += Eigen::Vector3d(noise(rng), noise(rng), noise(rng));
    out.push_back(n.normalized());
  }
  return out;
}

Eigen::Matrix3d turnDeg(double deg, const Eigen::Vector3d& axis) {
  return Eigen::AngleAxisd(deg * M_PI / 180.0, axis.normalized()).toRotationMatrix();
}

TEST(MapOrientation, FindsTheFloorAndTheWallsAmongClutter) {
  const std::vector<Eigen::Vector3d> normals = roomNormals(20000, 0.3, 0.6, 0.15, 1);
  const std::vector<Eigen::Vector3d> found = dominantDirections(normals);
  ASSERT_EQ(found.size(), 5u) << "floor and four walls (no ceiling in view)";
  for (const Eigen::Vector3d& axis : {Eigen::Vector3d(0, 0, 1), Eigen::Vector3d(1, 0, 0), Eigen::Vector3d(-1, 0, 0),
                                      Eigen::Vector3d(0, 1, 0), Eigen::Vector3d(0, -1, 0)}) {
    double nearest = 180;
    for (const Eigen::Vector3d& d : found) nearest = std::min(nearest, std::acos(std::min(1.0, d.dot(axis))) * 180 / M_PI);
    EXPECT_LT(nearest, 1.0) << "no direction found near " << axis.transpose();
  }
}

TEST(MapOrientation, TurnsNormalsPlacedThirteenDegreesOffBack) {
  const std::vector<Eigen::Vector3d> directions = dominantDirections(roomNormals(20000, 0.3, 0.6, 0.15, 2));
  // The ring corridor's placement after the cut at frame 600: 13.2 degrees, 10.8 of it heading.
  const Eigen::Matrix3d placement_error = turnDeg(13.2, Eigen::Vector3d(0.49, 0.29, -0.82));
  std::vector<Eigen::Vector3d> seen = roomNormals(5000, 0.25, 0.3, 0.2, 3);
  for (Eigen::Vector3d& n : seen) n = placement_error * n;
  const auto R = rotationOntoDirections(directions, seen, kMaxMapTurnDeg);
  ASSERT_TRUE(R.has_value());
  EXPECT_NEAR(angleDeg(*R), 13.2, 0.5);
  EXPECT_LT(angleDeg(*R * placement_error), 0.5) << "turned, but not back";
}

TEST(MapOrientation, OnePlaneOrATurnNearTheBuildingsSymmetryTurnsNothing) {
  const std::vector<Eigen::Vector3d> directions = dominantDirections(roomNormals(20000, 0.3, 0.6, 0.15, 4));
  std::vector<Eigen::Vector3d> floor_only = roomNormals(3000, 1.0, 0.5, 0.0, 5);
  for (Eigen::Vector3d& n : floor_only) n = turnDeg(10, Eigen::Vector3d::UnitZ()) * n;
  EXPECT_FALSE(rotationOntoDirections(directions, floor_only, kMaxMapTurnDeg).has_value())
      << "a floor alone says nothing about the heading";
  std::vector<Eigen::Vector3d> walls = roomNormals(3000, 0.0, 0.5, 0.0, 6);
  for (Eigen::Vector3d& n : walls) n = turnDeg(44, Eigen::Vector3d::UnitZ()) * n;
  EXPECT_FALSE(rotationOntoDirections(directions, walls, kMaxMapTurnDeg).has_value())
      << "walls 44 degrees off could as well be 46 degrees the other way";
}

// Keyframes whose clouds hold only normals (what the orientation reads), world normals from the
// room seen from a camera at `T_world_cam`.
Keyframe roomKeyframe(int index, int map, const Pose& T_world_cam, const Pose& placed, unsigned seed) {
  Keyframe k;
  k.frame_index = index;
  k.map = map;
  k.T_world_cam = placed;
  for (const Eigen::Vector3d& n : roomNormals(19200, 0.3, 0.5, 0.15, seed)) {
    const Eigen::Vector3d c = T_world_cam.linear().transpose() * n;
    k.cloud.normals.push_back(Vec3f{float(c.x()), float(c.y()), float(c.z())});
  }
  return k;
}

TEST(MapOrientation, ALaterMapIsTurnedAboutItsFirstKeyframeAndTheMapsAfterItWithIt) {
  std::vector<Pose> truth;
  for (int i = 0; i < 9; ++i) {
    Pose T = Pose::Identity();
    T.linear() = turnDeg(20.0 * i, Eigen::Vector3d::UnitZ()) * turnDeg(-100, Eigen::Vector3d::UnitX());
    T.translation() = Eigen::Vector3d(0.5 * i, 0.1 * i, 1.4);
    truth.push_back(T);
  }
  // Map 1 from keyframe 3 on, placed 12 degrees off about its first keyframe; map 2 from 6 on,
  // placed after it, so off by the same turn (and its own 3 degrees, below what is turned).
  auto aboutFirst = [&](const Eigen::Matrix3d& R, int first) {
    Pose turn = Pose::Identity();
    turn.linear() = R;
    turn.translation() = truth[size_t(first)].translation() - R * truth[size_t(first)].translation();
    return turn;
  };
  const Pose error1 = aboutFirst(turnDeg(12, Eigen::Vector3d(0.3, -0.2, 1.0)), 3);
  const Pose error2 = error1 * aboutFirst(turnDeg(3, Eigen::Vector3d(0, 0, 1)), 6);
  KeyframeStore store;
  for (int i = 0; i < 9; ++i) {
    const int map = i < 3 ? 0 : i < 6 ? 1 : 2;
    const Pose placed = map == 0 ? truth[size_t(i)] : map == 1 ? error1 * truth[size_t(i)] : error2 * truth[size_t(i)];
    store.add(roomKeyframe(10 * i, map, truth[size_t(i)], placed, 10 + unsigned(i)));
  }
  int turned = 0;
  const std::vector<Pose> oriented = orientLaterMaps(store, 5.0, &turned);
  EXPECT_EQ(turned, 1) << "map 2, 3 degrees off its predecessor, is below the 5 degrees turned";
  for (int i = 0; i < 3; ++i) EXPECT_TRUE(oriented[size_t(i)].isApprox(truth[size_t(i)])) << "the first map moved";
  for (int i = 3; i < 6; ++i)
    EXPECT_LT(angleDeg(oriented[size_t(i)].linear() * truth[size_t(i)].linear().transpose()), 0.5) << "keyframe " << i;
  EXPECT_LT((oriented[3].translation() - truth[3].translation()).norm(), 1e-9) << "turned about its first keyframe";
  for (int i = 6; i < 9; ++i)
    EXPECT_NEAR(angleDeg(oriented[size_t(i)].linear() * truth[size_t(i)].linear().transpose()), 3.0, 0.5)
        << "keyframe " << i << " did not turn with the map before it";
  EXPECT_EQ(orientLaterMaps(store, 15.0, &turned)[4].matrix(), store[4].T_world_cam.matrix());
  EXPECT_EQ(turned, 0);
}

}  // namespace
}  // namespace vf::slam
