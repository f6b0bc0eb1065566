// Record3dCapture on the shared iPhone capture and on small hand-made archives.
#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <cstring>
#include <functional>
#include <map>
#include <thread>

#include "core/error.h"
#include "io/lzfse.h"
#include "io/record3d.h"
#include "io/zip_archive.h"
#include "r3d_test_util.h"
#include "test_data.h"

namespace vf {
namespace {

using test::errorOf;

constexpr double kFx = 717.0636596679688, kCx = 359.244873046875, kCy = 485.18304443359375;

float medianValid(const DepthImage& d, int* valid = nullptr) {
  std::vector<float> v;
  for (int i = 0; i < d.width() * d.height(); ++i)
    if (d.data()[i] > 0) v.push_back(d.data()[i]);
  if (valid) *valid = int(v.size());
  if (v.empty()) return 0;
  std::nth_element(v.begin(), v.begin() + v.size() / 2, v.end());
  return v[v.size() / 2];
}

TEST(Record3d, IntrinsicsAreScaledFromRgbToDepthResolution) {
  VF_REQUIRE_DATA(r3d, "record3d_dance_head200.r3d");
  Record3dCapture cap(r3d);
  const Intrinsics k = cap.depthIntrinsics();
  EXPECT_EQ(k.width, 192);  // inferred: the metadata has no dw/dh
  EXPECT_EQ(k.height, 256);
  EXPECT_NEAR(k.fx, kFx * 192 / 720, 1e-3);  // 191.2170
  EXPECT_NEAR(k.fy, kFx * 256 / 960, 1e-3);
  EXPECT_NEAR(k.fx, 191.21698, 1e-3);
  EXPECT_NEAR(k.cx, kCx * 192 / 720, 1e-3);  // 95.7986
  EXPECT_NEAR(k.cy, kCy * 256 / 960, 1e-3);  // 129.3821
  EXPECT_NEAR(k.cx, 95.79863, 1e-3);
  EXPECT_NEAR(k.cy, 129.38215, 1e-3);
  EXPECT_EQ(cap.metadata().rgb_width, 720);
  EXPECT_EQ(cap.metadata().rgb_height, 960);
}

TEST(Record3d, FrameZeroDepthEqualsTheReferenceDecode) {
  VF_REQUIRE_DATA(r3d, "record3d_dance_head200.r3d");
  VF_REQUIRE_DATA(ref_path, "lzfse_reference/0.depth.decoded_f32_256x192");
  VF_REQUIRE_DATA(conf_path, "lzfse_reference/0.conf.decoded_u8_256x192");
  const auto ref_bytes = test::readFileBytes(ref_path);
  const auto conf = test::readFileBytes(conf_path);
  std::vector<float> ref(ref_bytes.size() / 4);
  std::memcpy(ref.data(), ref_bytes.data(), ref_bytes.size());

  Record3dOptions all;
  all.min_confidence = 0;
  const RgbdFrame f0 = Record3dCapture(r3d, all).load(0);
  const RgbdFrame f2 = Record3dCapture(r3d).load(0);  // default: high confidence only
  ASSERT_EQ(f0.depth.width(), 192);
  ASSERT_EQ(f0.depth.height(), 256);
  int kept_high = 0, expected_high = 0;
  for (size_t i = 0; i < ref.size(); ++i) {
    const float r = std::isfinite(ref[i]) && ref[i] > 0 ? ref[i] : 0.f;
    ASSERT_EQ(f0.depth.data()[i], r) << "pixel " << i;
    ASSERT_EQ(f2.depth.data()[i], conf[i] == 2 ? r : 0.f) << "pixel " << i;
    expected_high += (conf[i] == 2 && r > 0);
    kept_high += f2.depth.data()[i] > 0;
  }
  EXPECT_EQ(kept_high, expected_high);
  EXPECT_GT(expected_high, 192 * 256 / 2);
}

TEST(Record3d, AllFramesDecodeWithPlausibleDepthColorAndPoses) {
  VF_REQUIRE_DATA(r3d, "record3d_dance_head200.r3d");
  Record3dCapture cap(r3d);
  ASSERT_EQ(cap.size(), 200);
  ASSERT_EQ(cap.metadata().T_world_cam.size(), 200u);
  float min_median = 1e9f, max_median = 0;
  for (int i = 0; i < cap.size(); ++i) {
    const RgbdFrame f = cap.load(i);
    ASSERT_EQ(f.depth.width(), 192);
    ASSERT_EQ(f.depth.height(), 256);
    // Colour at the phone camera's own resolution (fused as is), depth at the LiDAR's.
    ASSERT_EQ(f.color.width(), 720);
    ASSERT_EQ(f.color.height(), 960);
    EXPECT_EQ(f.name, std::to_string(i));
    EXPECT_NEAR(f.timestamp, i / 30.0, 1e-9);
    ASSERT_TRUE(f.T_world_cam_given.has_value());
    int valid = 0;
    const float median = medianValid(f.depth, &valid);
    EXPECT_GT(valid, 192 * 256 / 4) << "frame " << i;
    min_median = std::min(min_median, median);
    max_median = std::max(max_median, median);
    double mean_green = 0;
    for (int p = 0; p < 720 * 960; ++p) mean_green += f.color.data()[p].g;
    mean_green /= 720 * 960;
    EXPECT_GT(mean_green, 20) << "frame " << i;  // an office in daylight, not a black image
    EXPECT_LT(mean_green, 235) << "frame " << i;
  }
  EXPECT_GT(min_median, 0.5f);
  EXPECT_LT(max_median, 5.0f);
  std::printf("median depth over frames: %.3f .. %.3f m\n", min_median, max_median);
}

TEST(Record3d, FirstPoseIsIdentityInArkitAxesSoDiagOneMinusOneMinusOneInOurs) {
  VF_REQUIRE_DATA(r3d, "record3d_dance_head200.r3d");
  Record3dCapture cap(r3d);
  const Pose T0 = cap.metadata().T_world_cam[0];
  // ARKit's first camera is the world frame (identity); our camera looks down its -z axis with
  // y flipped, so T_world_cam = diag(1, -1, -1) and zero translation.
  EXPECT_TRUE(T0.linear().isApprox(Eigen::Vector3d(1, -1, -1).asDiagonal().toDenseMatrix(), 1e-6))
      << T0.linear();
  EXPECT_LT(T0.translation().norm(), 1e-9);
  // The phone moves a little over 200 frames (6.7 s) but stays within a few metres.
  const Pose T199 = cap.metadata().T_world_cam[199];
  EXPECT_GT((T199.translation() - T0.translation()).norm(), 0.01);
  EXPECT_LT((T199.translation() - T0.translation()).norm(), 3.0);
  EXPECT_NEAR(T199.linear().determinant(), 1.0, 1e-9);
  // A point 1 m in front of camera 0 lies at world z = -1 (ARKit: camera looks down -z).
  const Eigen::Vector3d p = T0 * Eigen::Vector3d(0, 0, 1);
  EXPECT_NEAR(p.z(), -1.0, 1e-9);
}

TEST(Record3d, PoseConversionKeepsTheWorldAndFlipsCameraYAndZ) {
  // ARKit camera turned 90 degrees about world y (looking down world -x), placed at (1, 2, 3).
  const double s = std::sqrt(0.5);
  const Pose T = record3dPoseToCamera({0, s, 0, s, 1, 2, 3});
  EXPECT_TRUE(T.translation().isApprox(Eigen::Vector3d(1, 2, 3)));
  // Our +z (forward) is ARKit's -z, which the rotation maps to world -x.
  EXPECT_TRUE((T.linear() * Eigen::Vector3d::UnitZ()).isApprox(Eigen::Vector3d(-1, 0, 0), 1e-12));
  // Our +y (down) is world -y.
  EXPECT_TRUE((T.linear() * Eigen::Vector3d::UnitY()).isApprox(Eigen::Vector3d(0, -1, 0), 1e-12));
}

TEST(Record3d, ConcurrentLoadsMatchSerialLoads) {
  VF_REQUIRE_DATA(r3d, "record3d_dance_head200.r3d");
  Record3dCapture cap(r3d);
  const int n = 24;
  std::vector<RgbdFrame> serial, parallel(n);
  for (int i = 0; i < n; ++i) serial.push_back(cap.load(i));
  std::vector<std::thread> threads;
  for (int t = 0; t < 4; ++t)
    threads.emplace_back([&, t] {
      for (int i = t; i < n; i += 4) parallel[i] = cap.load(i);
    });
  for (auto& th : threads) th.join();
  for (int i = 0; i < n; ++i) {
    ASSERT_EQ(0, std::memcmp(serial[i].depth.data(), parallel[i].depth.data(), 192 * 256 * 4));
    ASSERT_EQ(0, std::memcmp(serial[i].color.data(), parallel[i].color.data(), 192 * 256 * 4));
  }
}

// A two-frame archive made from frame 0's real entries, with `patch` applied to the entry map.
std::string makeArchive(const std::string& name,
                        const std::function<void(std::map<std::string, std::vector<uint8_t>>&)>& patch) {
  const std::string r3d = test::dataPath("record3d_dance_head200.r3d");
  ZipArchive src(r3d);
  std::map<std::string, std::vector<uint8_t>> e;
  e["metadata"] = test::toBytes(
      R"({"w":720,"h":960,"dw":192,"dh":256,"fps":60,"K":[717.0636596679688,0,0,0,717.0636596679688,0,359.244873046875,485.18304443359375,1],)"
      R"("poses":[[0,0,0,1,0,0,0],[0,0,0,1,0.5,0,0]],"frameTimestamps":[10.0,10.25]})");
  for (int i = 0; i < 2; ++i)
    for (const char* ext : {".jpg", ".depth", ".conf"})
      e["rgbd/" + std::to_string(i) + ext] = src.read("rgbd/0" + std::string(ext));
  patch(e);
  const std::string path = test::tempDir("r3d_" + name) + "/capture.r3d";
  test::writeZip(path, e);
  return path;
}

TEST(Record3dArchive, MetadataTimestampsAndSizesAreUsed) {
  VF_REQUIRE_DATA(r3d, "record3d_dance_head200.r3d");
  const std::string path = makeArchive("ok", [](auto&) {});
  Record3dCapture cap(path);
  ASSERT_EQ(cap.size(), 2);
  EXPECT_DOUBLE_EQ(cap.load(1).timestamp, 10.25);
  EXPECT_NEAR(cap.load(1).T_world_cam_given->translation().x(), 0.5, 1e-12);
}

TEST(Record3dArchive, BrokenEntriesThrowNamingFileAndEntry) {
  VF_REQUIRE_DATA(r3d, "record3d_dance_head200.r3d");
  struct Case {
    const char* name;
    std::function<void(std::map<std::string, std::vector<uint8_t>>&)> patch;
    const char* entry;  // expected in the message
    bool at_open;
  };
  const std::vector<Case> cases = {
      {"nometa", [](auto& e) { e.erase("metadata"); }, "metadata", true},
      {"badjson", [](auto& e) { e["metadata"] = test::toBytes("{\"w\": 720,"); }, "metadata", true},
      {"noK", [](auto& e) { e["metadata"] = test::toBytes(R"({"w":720,"h":960,"fps":30})"); }, "K", true},
      {"nojpg", [](auto& e) { e.erase("rgbd/1.jpg"); }, "rgbd/1.jpg", false},
      {"noconf", [](auto& e) { e.erase("rgbd/1.conf"); }, "rgbd/1.conf", false},
      {"wrongsize", [](auto& e) { e["rgbd/1.depth"] = e["rgbd/1.conf"]; }, "rgbd/1.depth", false},
      {"truncated", [](auto& e) { e["rgbd/1.depth"].resize(20000); }, "rgbd/1.depth", false},
      {"flipped", [](auto& e) { for (size_t i = 200; i < 20000; i += 7) e["rgbd/1.depth"][i] ^= 0x5a; },
       "rgbd/1.depth", false},
      {"badjpg", [](auto& e) { e["rgbd/1.jpg"].resize(10); }, "rgbd/1.jpg", false},
  };
  for (const Case& c : cases) {
    const std::string path = makeArchive(c.name, c.patch);
    const std::string msg = errorOf([&] {
      Record3dCapture cap(path);
      cap.load(0);
      cap.load(1);
    });
    EXPECT_NE(msg.find(path), std::string::npos) << c.name << ": " << msg;
    EXPECT_NE(msg.find(c.entry), std::string::npos) << c.name << ": " << msg;
    if (!c.at_open) {
      EXPECT_NO_THROW(Record3dCapture(path).load(0)) << c.name;
    }
  }
}

TEST(Record3dArchive, OptionRangeIsChecked) {
  VF_REQUIRE_DATA(r3d, "record3d_dance_head200.r3d");
  Record3dOptions o;
  o.min_confidence = 3;
  EXPECT_THROW(Record3dCapture(r3d, o), Error);
}

}  // namespace
}  // namespace vf
