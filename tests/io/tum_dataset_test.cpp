#include <gtest/gtest.h>

#include <algorithm>
#include <chrono>
#include <cstdlib>
#include <cmath>
#include <filesystem>
#include <fstream>
#include <functional>
#include <future>
#include <vector>

#include "io/image_io.h"
#include "io/tum_dataset.h"
#include "test_data.h"

namespace vf {
namespace {

using test::errorOf;

namespace fs = std::filesystem;

// A crafted TUM folder: depth frames at `depth_t`, colour frames at `rgb_t`, images w x h.
struct CraftedTum {
  std::string dir;
  CraftedTum(const std::string& name, const std::vector<double>& depth_t, const std::vector<double>& rgb_t,
             int w = 8, int h = 6, bool intrinsics_file = true, const std::string& rgb_header = "# color images\n")
      : dir(test::tempDir(name)) {
    fs::create_directories(dir + "/rgb");
    fs::create_directories(dir + "/depth");
    std::ofstream d(dir + "/depth.txt"), r(dir + "/rgb.txt");
    d << "# depth maps\n# timestamp filename\n";
    r << rgb_header << "# timestamp filename\n";
    char name_buf[64];
    for (double t : depth_t) {
      std::snprintf(name_buf, sizeof name_buf, "depth/%.6f.png", t);
      d << std::fixed << t << " " << name_buf << "\n";
      writeDepthPng(dir + "/" + name_buf, DepthImage(w, h, 1.0f));
    }
    for (double t : rgb_t) {
      std::snprintf(name_buf, sizeof name_buf, "rgb/%.6f.png", t);
      r << std::fixed << t << " " << name_buf << "\n";
      writeColorPng(dir + "/" + name_buf, ColorImage(w, h, Rgb8{10, 20, 30, 255}));
    }
    if (intrinsics_file) std::ofstream(dir + "/camera_intrinsics.txt") << "# fx fy cx cy\n100 101 3.5 2.5\n";
  }
};

TEST(TumAssociation, GreedyNearestWithinToleranceEachUsedOnce) {
  // depth 1.00 and 1.01 both want rgb 1.005 (diff 0.005 each); the tie goes to depth 1.00 (first
  // by index) and 1.01 takes 1.025 (0.015). depth 2.0 has nothing within 0.02 s (2.021 is 0.021).
  const std::vector<double> depth = {1.00, 1.01, 2.0, 3.0};
  const std::vector<double> rgb = {1.005, 1.025, 2.021, 2.995};
  const auto m = associateTimestamps(depth, rgb, 0.02);
  ASSERT_EQ(m.size(), 3u);
  EXPECT_EQ(m[0], std::make_pair(0, 0));
  EXPECT_EQ(m[1], std::make_pair(1, 1));
  EXPECT_EQ(m[2], std::make_pair(3, 3));
}

TEST(TumAssociation, SmallestDifferenceWinsOverListOrder) {
  // depth 1.015 is closer to rgb 1.010 (0.005) than depth 1.000 is (0.010): it takes it, and
  // depth 1.000 gets nothing else within 0.02 s.
  const auto m = associateTimestamps({1.000, 1.015}, {1.010}, 0.02);
  ASSERT_EQ(m.size(), 1u);
  EXPECT_EQ(m[0], std::make_pair(1, 0));
}

TEST(TumDataset, CraftedFolderFusesAndReportsTheFrameWithoutColour) {
  const CraftedTum tum("tum_crafted_all", {10.000, 10.033, 10.100, 10.133}, {10.010, 10.040, 10.140});
  const TumDataset ds(tum.dir);
  ASSERT_EQ(ds.size(), 4);
  EXPECT_EQ(ds.unassociatedCount(), 1);
  ASSERT_EQ(ds.warnings().size(), 1u);
  EXPECT_NE(ds.warnings()[0].find("depth/10.100000.png"), std::string::npos) << ds.warnings()[0];
  EXPECT_NE(ds.warnings()[0].find("fused without colour"), std::string::npos) << ds.warnings()[0];
  const RgbdFrame no_color = ds.load(2);
  EXPECT_TRUE(no_color.color.empty());
  EXPECT_FLOAT_EQ(no_color.depth(3, 3), 1.0f);
  EXPECT_EQ(ds.colorPath(2), "");
  // A colour image may serve two depth frames: 10.133 takes 10.140 like 10.100 would have.
  EXPECT_EQ(ds.colorPath(3), tum.dir + "/rgb/10.140000.png");
}

TEST(TumDataset, ExclusivePairingLeavesOutAndReportsTheUnassociatedFrame) {
  const CraftedTum tum("tum_crafted", {10.000, 10.033, 10.100, 10.133}, {10.010, 10.040, 10.140});
  TumOptions options;
  options.exclusive_color = true;
  const TumDataset ds(tum.dir, options);
  ASSERT_EQ(ds.size(), 3);
  EXPECT_EQ(ds.unassociatedCount(), 1);
  ASSERT_EQ(ds.warnings().size(), 1u);
  EXPECT_NE(ds.warnings()[0].find("depth/10.100000.png"), std::string::npos) << ds.warnings()[0];
  // Depth order is kept and names/timestamps come from the depth files.
  EXPECT_DOUBLE_EQ(ds.timestamp(0), 10.000);
  EXPECT_DOUBLE_EQ(ds.timestamp(2), 10.133);
  const RgbdFrame f = ds.load(2);
  EXPECT_EQ(f.name, "10.133000");
  EXPECT_DOUBLE_EQ(f.timestamp, 10.133);
  EXPECT_EQ(ds.colorPath(2), tum.dir + "/rgb/10.140000.png");
  EXPECT_FLOAT_EQ(f.depth(3, 3), 1.0f);
  EXPECT_EQ(f.color(3, 3).g, 20);
  const Intrinsics k = ds.depthIntrinsics();
  EXPECT_FLOAT_EQ(k.fx, 100.f);
  EXPECT_FLOAT_EQ(k.fy, 101.f);
  EXPECT_EQ(k.width, 8);
  EXPECT_EQ(k.height, 6);
  EXPECT_TRUE(ds.depthDistortion().isZero());
}

// nearestInTime against the scan over every pair it replaced (the colour pairing: ties to the one
// listed last) and poseNearTimestamp (ties to the first), on times with many exact ties and
// unsorted lists.
TEST(TumAssociation, NearestInTimeMatchesTheScanOverEveryPair) {
  std::srand(35);
  for (int trial = 0; trial < 200; ++trial) {
    std::vector<double> times, candidates;
    for (int i = 0; i < 1 + std::rand() % 30; ++i) times.push_back(std::rand() % 40);
    for (int j = 0; j < std::rand() % 30; ++j) candidates.push_back(std::rand() % 40);
    const double max_difference = std::rand() % 4;
    for (const bool prefer_last : {true, false}) {
      const std::vector<int> fast = nearestInTime(times, candidates, max_difference, prefer_last);
      ASSERT_EQ(fast.size(), times.size());
      for (size_t i = 0; i < times.size(); ++i) {
        double best = max_difference;
        int expected = -1;
        for (size_t j = 0; j < candidates.size(); ++j) {
          const double d = std::abs(candidates[j] - times[i]);
          if (prefer_last ? d <= best : (d < best || (d == best && expected < 0))) best = d, expected = int(j);
        }
        EXPECT_EQ(fast[i], expected) << "trial " << trial << ", time " << times[i] << ", prefer_last " << prefer_last;
      }
    }
  }
}

// Cause 11: the pairing compared every depth frame with every colour image; two lists of 200,000
// lines (6 MB each) took minutes before the first frame. Only frame 0's images exist: opening
// reads no other, and every depth line names frame 0's image.
TEST(TumDataset, LongListsOpenInSeconds) {
  const CraftedTum tum("tum_long_lists", {1000.0}, {1000.0});
  constexpr int kLines = 200000;
  std::string depth = "# depth maps\n", rgb = "# color images\n", gt = "# ground truth\n";
  char line[128];
  for (int i = 0; i < kLines; ++i) {
    const double t = 1000.0 + i / 30.0;
    const std::string name = i == 0 ? "1000.000000" : std::to_string(i);
    std::snprintf(line, sizeof line, "%.6f depth/1000.000000.png\n", t);  // one file at every time: allowed
    depth += line;
    std::snprintf(line, sizeof line, "%.6f rgb/%s.png\n", t + (i == 0 ? 0 : 0.004), name.c_str());
    rgb += line;
    std::snprintf(line, sizeof line, "%.6f %d 0 0 0 0 0 1\n", t + 0.001, i);
    gt += line;
  }
  std::ofstream(tum.dir + "/depth.txt") << depth;
  std::ofstream(tum.dir + "/rgb.txt") << rgb;
  std::ofstream(tum.dir + "/groundtruth.txt") << gt;
  const auto start = std::chrono::steady_clock::now();
  const TumDataset ds(tum.dir);
  const double seconds = std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
  EXPECT_LT(seconds, 20.0) << "n log n: about a second on an idle machine (the pairing of every pair: 48 s)";
  ASSERT_EQ(ds.size(), kLines);
  EXPECT_EQ(ds.colorPath(kLines - 1), tum.dir + "/rgb/" + std::to_string(kLines - 1) + ".png");
  ASSERT_TRUE(ds.groundTruthAt(kLines - 1));
  EXPECT_DOUBLE_EQ(ds.groundTruthAt(kLines - 1)->translation().x(), kLines - 1);
}

// Cause 12: a line repeated in depth.txt (or two lines of one time) fused that frame twice, and
// `evaluate` then refused the trajectory written (two poses at one time).
TEST(TumDataset, RepeatedTimesInTheListsAreRefusedNamingBothLines) {
  const CraftedTum tum("tum_repeated_lines", {10.000, 10.033, 10.067}, {10.000, 10.033, 10.067});
  std::ofstream(tum.dir + "/depth.txt", std::ios::app) << "10.033000 depth/10.033000.png\n";
  std::string e = errorOf([&] { TumDataset ds(tum.dir); });
  EXPECT_NE(e.find(tum.dir + "/depth.txt:4 and line 6 list the same timestamp 10.033000"), std::string::npos) << e;

  // Times equal to the microsecond a TUM list (and the trajectory written) carries.
  const CraftedTum close("tum_repeated_micro", {10.000, 10.033}, {10.000, 10.033});
  std::ofstream(close.dir + "/depth.txt", std::ios::app) << "10.0330001 depth/10.033000b.png\n";
  e = errorOf([&] { TumDataset ds(close.dir); });
  EXPECT_NE(e.find("depth.txt:4 and line 5 list the same timestamp 10.033000"), std::string::npos) << e;

  const CraftedTum color("tum_repeated_rgb", {10.000, 10.033}, {10.000, 10.033});
  std::ofstream(color.dir + "/rgb.txt", std::ios::app) << "10.000000 rgb/10.033000.png\n";
  e = errorOf([&] { TumDataset ds(color.dir); });
  EXPECT_NE(e.find("rgb.txt:3 and line 5 list the same timestamp 10.000000"), std::string::npos) << e;
}

// Cause 19: a camera_intrinsics.txt the pipeline cannot fuse was reported as
// "Intrinsics.cx (--intrinsics)", an option not given; the reader names the file.
TEST(TumIntrinsics, ACameraFileThatCannotBeFusedNamesIt) {
  const CraftedTum tum("tum_bad_camera", {1.0}, {1.0});
  std::ofstream(tum.dir + "/camera_intrinsics.txt") << "# fx fy cx cy\n100 101 300 2.5\n";
  const std::string e = errorOf([&] { TumDataset ds(tum.dir); });
  EXPECT_NE(e.find(tum.dir + "/camera_intrinsics.txt: cx = 300 lies outside the 8-pixel-wide image"), std::string::npos)
      << e;
  EXPECT_EQ(e.find("--intrinsics"), std::string::npos) << e;
}

TEST(TumIntrinsics, ParseOverride) {
  const PinholeOverride o = parsePinholeOverride("525, 526.5,319.5,239.5");
  EXPECT_FLOAT_EQ(o.fx, 525.f);
  EXPECT_FLOAT_EQ(o.fy, 526.5f);
  EXPECT_FLOAT_EQ(o.cx, 319.5f);
  EXPECT_FLOAT_EQ(o.cy, 239.5f);
  EXPECT_NE(errorOf([] { parsePinholeOverride("525,525,319.5"); }).find("fx,fy,cx,cy"), std::string::npos);
  EXPECT_THROW(parsePinholeOverride("525,525,abc,239.5"), Error);
  EXPECT_THROW(parsePinholeOverride("525 525 319.5 239.5"), Error);
  EXPECT_THROW(parsePinholeOverride("-525,525,319.5,239.5"), Error);
}

TEST(TumIntrinsics, PublishedValuesByName) {
  EXPECT_FLOAT_EQ(publishedTumCalibration("rgbd_dataset_freiburg2_desk")->fx, 520.908620f);
  EXPECT_FLOAT_EQ(publishedTumCalibration("tum_fr3_teddy_head60")->fy, 539.2f);
  EXPECT_TRUE(publishedTumCalibration("tum_fr3_teddy_head60")->distortion.isZero());
  EXPECT_FLOAT_EQ(publishedTumCalibration("# file: 'rgbd_dataset_freiburg1_xyz.bag'")->distortion.k1, 0.262383f);
  EXPECT_FALSE(publishedTumCalibration("my_frame_data").has_value());  // "fr" inside words is no hint
  EXPECT_FALSE(publishedTumCalibration("fr12").has_value());
}

TEST(TumIntrinsics, PriorityOverrideThenFileThenNameThenHeader) {
  // File present: it beats the folder name.
  const CraftedTum with_file("tum_prio_freiburg3_file", {1.0}, {1.0});
  EXPECT_FLOAT_EQ(TumDataset(with_file.dir).depthIntrinsics().fx, 100.f);
  // Override beats the file.
  TumOptions o;
  o.intrinsics = parsePinholeOverride("200,201,4,3");
  const TumDataset overridden(with_file.dir, o);
  EXPECT_FLOAT_EQ(overridden.depthIntrinsics().fx, 200.f);
  EXPECT_EQ(overridden.calibration().source, "--intrinsics");
  // No file: the folder name (images of the published camera's size, which it is checked against).
  const CraftedTum by_name("tum_prio_freiburg3_name", {1.0}, {1.0}, 640, 480, false);
  EXPECT_FLOAT_EQ(TumDataset(by_name.dir).depthIntrinsics().fx, 535.4f);
  // No file, anonymous folder: the rgb.txt header.
  const CraftedTum by_header("tum_prio_anonymous", {1.0}, {1.0}, 640, 480, false,
                             "# color images\n# file: 'rgbd_dataset_freiburg2_desk.bag'\n");
  EXPECT_FLOAT_EQ(TumDataset(by_header.dir).depthIntrinsics().fx, 520.908620f);
  // Nothing at all: the error says what to pass.
  const CraftedTum nothing("tum_prio_nothing", {1.0}, {1.0}, 8, 6, false);
  EXPECT_NE(errorOf([&] { TumDataset ds(nothing.dir); }).find("--intrinsics"), std::string::npos);
}

TEST(TumIntrinsics, CameraFileWithDistortionAndMalformedLine) {
  const std::string dir = test::tempDir("tum_calib_file");
  std::ofstream(dir + "/a.txt") << "# fx fy cx cy\n517.3 516.5 318.6 255.3\n# k1 k2 p1 p2 k3\n0.26 -0.95 -0.005 0.002 1.16\n";
  const Calibration c = readCameraIntrinsicsFile(dir + "/a.txt");
  EXPECT_FLOAT_EQ(c.cy, 255.3f);
  EXPECT_FLOAT_EQ(c.distortion.k3, 1.16f);
  std::ofstream(dir + "/b.txt") << "# fx fy cx cy\n517.3 516.5 318.6\n";
  EXPECT_NE(errorOf([&] { readCameraIntrinsicsFile(dir + "/b.txt"); }).find(dir + "/b.txt:2"), std::string::npos);
}

TEST(TumDataset, ErrorsNameTheFile) {
  EXPECT_NE(errorOf([] { TumDataset ds("/nonexistent/tum"); }).find("/nonexistent/tum"), std::string::npos);

  const CraftedTum no_list("tum_err_nolist", {1.0}, {1.0});
  fs::remove(no_list.dir + "/rgb.txt");
  EXPECT_NE(errorOf([&] { TumDataset ds(no_list.dir); }).find(no_list.dir + "/rgb.txt"), std::string::npos);

  const CraftedTum empty("tum_err_empty", {1.0}, {1.0});
  std::ofstream(empty.dir + "/depth.txt") << "# depth maps\n# timestamp filename\n";
  const std::string empty_msg = errorOf([&] { TumDataset ds(empty.dir); });
  EXPECT_NE(empty_msg.find(empty.dir + "/depth.txt"), std::string::npos) << empty_msg;
  EXPECT_NE(empty_msg.find("no images"), std::string::npos) << empty_msg;

  const CraftedTum sizes("tum_err_sizes", {1.0}, {1.0});
  writeColorPng(sizes.dir + "/rgb/1.000000.png", ColorImage(10, 6));
  const std::string size_msg = errorOf([&] { TumDataset ds(sizes.dir); });
  EXPECT_NE(size_msg.find(sizes.dir + "/rgb/1.000000.png"), std::string::npos) << size_msg;
  EXPECT_NE(size_msg.find("10x6"), std::string::npos) << size_msg;

  const CraftedTum eight("tum_err_8bit", {1.0, 2.0}, {1.0, 2.0});
  writeLabelPng(eight.dir + "/depth/2.000000.png", LabelImage(8, 6, 1));  // 8-bit
  const TumDataset ds(eight.dir);
  const std::string eight_msg = errorOf([&] { ds.load(1); });
  EXPECT_NE(eight_msg.find(eight.dir + "/depth/2.000000.png"), std::string::npos) << eight_msg;
  EXPECT_NE(eight_msg.find("16-bit"), std::string::npos) << eight_msg;

  std::ofstream(eight.dir + "/depth/2.000000.png") << "truncated";
  EXPECT_NE(errorOf([&] { ds.load(1); }).find(eight.dir + "/depth/2.000000.png"), std::string::npos);

  const CraftedTum malformed("tum_err_line", {1.0}, {1.0});
  std::ofstream(malformed.dir + "/rgb.txt") << "# c\nabc rgb/1.000000.png\n";
  EXPECT_NE(errorOf([&] { TumDataset d(malformed.dir); }).find(malformed.dir + "/rgb.txt:2"), std::string::npos);
}

TEST(TumDatasetReal, Freiburg1XyzHead100) {
  VF_REQUIRE_DATA(dir, "tum_fr1_xyz_head100");
  // Every one of the 100 depth frames has a colour image within 0.02 s when images may be shared.
  EXPECT_EQ(TumDataset(dir).size(), 100);
  EXPECT_EQ(TumDataset(dir).unassociatedCount(), 0);
  TumOptions exclusive;
  exclusive.exclusive_color = true;
  const TumDataset ds(dir, exclusive);
  // TUM's associate.py (greedy, 0.02 s, one-to-one) pairs 95 of them: rgb 1305031102.211214
  // is nearer to depth .226738 (15.5 ms) than to .194330 (16.9 ms), so .194330 has no partner left.
  // Same for .494271, .594158, .894167 and 1305031103.191061.
  EXPECT_EQ(ds.size(), 95);
  EXPECT_EQ(ds.unassociatedCount(), 5);
  ASSERT_EQ(ds.warnings().size(), 5u);
  EXPECT_NE(ds.warnings()[0].find("depth/1305031102.194330.png"), std::string::npos) << ds.warnings()[0];
  const Intrinsics k = ds.depthIntrinsics();
  EXPECT_EQ(k.width, 640);
  EXPECT_EQ(k.height, 480);
  EXPECT_NEAR(k.fx, 517.306408, 1e-3);
  EXPECT_NEAR(ds.calibration().distortion.k1, 0.262383, 1e-6);
  EXPECT_TRUE(ds.depthDistortion().isZero());  // delivered undistorted

  const RgbdFrame f = ds.load(0);
  EXPECT_EQ(f.name, "1305031102.160407");
  EXPECT_DOUBLE_EQ(f.timestamp, 1305031102.160407);
  ASSERT_EQ(f.color.width(), 640);
  std::vector<float> valid;
  for (int i = 0; i < 640 * 480; ++i)
    if (f.depth.data()[i] > 0) valid.push_back(f.depth.data()[i]);
  ASSERT_GT(valid.size(), 640u * 480u / 2);  // a Kinect sees most of a desk scene
  std::nth_element(valid.begin(), valid.begin() + valid.size() / 2, valid.end());
  const float median_m = valid[valid.size() / 2];
  EXPECT_GT(median_m, 0.5f);
  EXPECT_LT(median_m, 3.0f);
  // Depth values stay on the sensor's 0.2 mm grid: nearest-neighbour undistortion never blends.
  for (size_t i = 0; i < valid.size(); i += 97)
    EXPECT_NEAR(valid[i] * 5000.f, std::round(valid[i] * 5000.f), 1e-2f) << valid[i];

  // The mocap pose of the first frame is attached (groundtruth 1305031102.1558, within 0.02 s).
  ASSERT_TRUE(f.T_world_cam_given.has_value());
  EXPECT_NEAR(f.T_world_cam_given->translation().x(), 1.3452, 1e-9);
  EXPECT_GT(ds.groundTruth().size(), 300u);
}

TEST(TumDatasetReal, UndistortionMovesPixelsOnlyTowardsTheBorder) {
  VF_REQUIRE_DATA(dir, "tum_fr1_xyz_head100");
  TumOptions raw_options;
  raw_options.undistort = false;
  const TumDataset raw(dir, raw_options), undistorted(dir);
  EXPECT_NEAR(raw.depthDistortion().k1, 0.262383, 1e-6);
  const RgbdFrame a = raw.load(5), b = undistorted.load(5);
  // The principal point does not move.
  EXPECT_EQ(a.depth(318, 255), b.depth(318, 255));
  // Every undistorted depth value is a raw value from the same frame (nearest neighbour).
  std::vector<float> raw_values(a.depth.data(), a.depth.data() + 640 * 480);
  std::sort(raw_values.begin(), raw_values.end());
  int invented = 0;
  for (int i = 0; i < 640 * 480; i += 13)
    invented += !std::binary_search(raw_values.begin(), raw_values.end(), b.depth.data()[i]);
  EXPECT_EQ(invented, 0);
  int changed = 0;
  for (int i = 0; i < 640 * 480; ++i) changed += a.depth.data()[i] != b.depth.data()[i];
  EXPECT_GT(changed, 640 * 480 / 10);  // k1 = 0.26 moves the periphery by pixels
}

TEST(TumDatasetReal, ConcurrentLoadsMatchSequentialLoads) {
  VF_REQUIRE_DATA(dir, "tum_fr1_xyz_head100");
  const TumDataset ds(dir);
  std::vector<std::future<RgbdFrame>> futures;
  for (int i = 0; i < 8; ++i) futures.push_back(std::async(std::launch::async, [&ds, i] { return ds.load(i * 12); }));
  for (int i = 0; i < 8; ++i) {
    const RgbdFrame parallel = futures[size_t(i)].get();
    const RgbdFrame sequential = ds.load(i * 12);
    EXPECT_TRUE(std::equal(parallel.depth.data(), parallel.depth.data() + 640 * 480, sequential.depth.data()));
    EXPECT_EQ(parallel.name, sequential.name);
  }
}

TEST(TumDatasetReal, Freiburg3TeddyUsesItsFileWithoutUndistortion) {
  VF_REQUIRE_DATA(dir, "tum_fr3_teddy_head60");
  const TumDataset ds(dir);
  EXPECT_EQ(ds.size() + ds.unassociatedCount(), 60);
  EXPECT_FLOAT_EQ(ds.depthIntrinsics().fx, 535.4f);
  EXPECT_TRUE(ds.calibration().distortion.isZero());
}

}  // namespace
}  // namespace vf
