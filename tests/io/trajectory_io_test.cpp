#include <gtest/gtest.h>

#include <fstream>
#include <functional>

#include "io/trajectory_io.h"
#include "test_data.h"

namespace vf {
namespace {

using test::errorOf;

TEST(TrajectoryIo, RoundTripKeepsMicrosecondsAndSubMicrometres) {
  const std::string dir = test::tempDir("trajectory_io");
  Trajectory t;
  for (int i = 0; i < 5; ++i) {
    StampedPose p;
    p.timestamp = 1305031102.160407 + 0.033 * i;
    p.T_world_cam = Eigen::Translation3d(1.2345678 + i, -0.5, 2.0 * i) *
                    Eigen::AngleAxisd(0.3 * i + 0.1, Eigen::Vector3d(1, 2, 3).normalized());
    t.push_back(p);
  }
  writeTumTrajectory(dir + "/t.txt", t);
  const Trajectory back = readTumTrajectory(dir + "/t.txt");
  ASSERT_EQ(back.size(), t.size());
  for (size_t i = 0; i < t.size(); ++i) {
    EXPECT_NEAR(back[i].timestamp, t[i].timestamp, 1e-6);
    EXPECT_LT((back[i].T_world_cam.translation() - t[i].T_world_cam.translation()).norm(), 1e-8);
    EXPECT_LT((back[i].T_world_cam.linear() - t[i].T_world_cam.linear()).norm(), 1e-8);
  }
}

TEST(TrajectoryIo, ReadsTumGroundTruth) {
  VF_REQUIRE_DATA(path, "tum_fr1_xyz_head100/groundtruth.txt");
  const Trajectory gt = readTumTrajectory(path);
  ASSERT_GT(gt.size(), 300u);
  // First line: 1305031102.0658 1.3669 0.6305 1.6860 0.6606 0.6046 -0.2937 -0.3344
  EXPECT_DOUBLE_EQ(gt[0].timestamp, 1305031102.0658);
  EXPECT_DOUBLE_EQ(gt[0].T_world_cam.translation().z(), 1.6860);
  const Eigen::Quaterniond q(gt[0].T_world_cam.linear());
  const Eigen::Quaterniond expected = Eigen::Quaterniond(-0.3344, 0.6606, 0.6046, -0.2937).normalized();
  EXPECT_NEAR(std::abs(q.dot(expected)), 1.0, 1e-12);
}

TEST(TrajectoryIo, MalformedLinesNameFileAndLine) {
  const std::string dir = test::tempDir("trajectory_io_bad");
  std::ofstream(dir + "/a.txt") << "# header\n1.0 0 0 0 0 0 0 1\n2.0 0 0 0 0 0 1\n";
  EXPECT_NE(errorOf([&] { readTumTrajectory(dir + "/a.txt"); }).find(dir + "/a.txt:3"), std::string::npos);
  std::ofstream(dir + "/b.txt") << "1.0 0 0 x 0 0 0 1\n";
  EXPECT_NE(errorOf([&] { readTumTrajectory(dir + "/b.txt"); }).find(dir + "/b.txt:1"), std::string::npos);
  std::ofstream(dir + "/c.txt") << "1.0 0 0 0 0 0 0 0\n";
  EXPECT_NE(errorOf([&] { readTumTrajectory(dir + "/c.txt"); }).find("zero length"), std::string::npos);
  std::ofstream(dir + "/d.txt") << "# only comments\n";
  EXPECT_THROW(readTumTrajectory(dir + "/d.txt"), Error);
  EXPECT_THROW(readTumTrajectory(dir + "/missing.txt"), Error);
}

}  // namespace
}  // namespace vf
