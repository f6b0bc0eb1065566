// Record3D -> TUM conversion, checked by re-reading the written files directly.
#include <gtest/gtest.h>

#include <opencv2/imgcodecs.hpp>

#include <cmath>
#include <filesystem>
#include <fstream>
#include <sstream>

#include "core/error.h"
#include "io/frame_list_source.h"
#include "io/record3d.h"
#include "io/tum_writer.h"
#include "test_data.h"

namespace vf {
namespace {
namespace fs = std::filesystem;

std::vector<std::vector<std::string>> dataLines(const std::string& path) {
  std::ifstream f(path);
  EXPECT_TRUE(f.good()) << path;
  std::vector<std::vector<std::string>> out;
  std::string line;
  while (std::getline(f, line)) {
    if (line.empty() || line[0] == '#') continue;
    std::istringstream s(line);
    std::vector<std::string> fields;
    for (std::string w; s >> w;) fields.push_back(w);
    out.push_back(fields);
  }
  return out;
}

TEST(TumWriter, FiveRecord3dFramesRoundTrip) {
  VF_REQUIRE_DATA(r3d, "record3d_dance_head200.r3d");
  Record3dCapture cap(r3d);
  const std::string dir = test::tempDir("tum_writer") + "/out";
  TumWriteOptions options;
  options.max_frames = 5;
  const TumWriteResult result = writeTumFolder(cap, dir, options);
  EXPECT_EQ(result.frames, 5);
  EXPECT_EQ(result.poses, 5);

  const auto depth_list = dataLines(dir + "/depth.txt");
  const auto rgb_list = dataLines(dir + "/rgb.txt");
  const auto gt = dataLines(dir + "/groundtruth.txt");
  ASSERT_EQ(depth_list.size(), 5u);
  ASSERT_EQ(rgb_list.size(), 5u);
  ASSERT_EQ(gt.size(), 5u);
  EXPECT_EQ(depth_list[1][0], "0.033333");
  EXPECT_EQ(depth_list[1][1], "depth/0.033333.png");
  EXPECT_EQ(rgb_list[4][1], "rgb/0.133333.png");

  for (int i = 0; i < 5; ++i) {
    const RgbdFrame f = cap.load(i);
    const cv::Mat depth = cv::imread(dir + "/" + depth_list[i][1], cv::IMREAD_UNCHANGED);
    ASSERT_EQ(depth.type(), CV_16UC1);
    ASSERT_EQ(depth.cols, 192);
    ASSERT_EQ(depth.rows, 256);
    int valid = 0;
    for (int y = 0; y < 256; ++y)
      for (int x = 0; x < 192; ++x) {
        const float d = f.depth(x, y);
        const float back = depth.at<uint16_t>(y, x) / 5000.f;
        if (d == 0.f) {
          ASSERT_EQ(back, 0.f);
        } else {
          ASSERT_NEAR(back, d, 0.5f / 5000.f + 1e-6f) << x << "," << y;
          ++valid;
        }
      }
    EXPECT_GT(valid, 192 * 256 / 4);
    // TUM pairs colour with depth pixel for pixel: the phone's 720x960 colour comes out
    // averaged to the depth size.
    const cv::Mat rgb = cv::imread(dir + "/" + rgb_list[i][1], cv::IMREAD_COLOR);
    ASSERT_EQ(rgb.cols, 192);
    ASSERT_EQ(rgb.rows, 256);
    const ColorImage small = resizeColorArea(f.color, 192, 256);
    for (int y = 0; y < 256; y += 17)
      for (int x = 0; x < 192; x += 13) {
        const cv::Vec3b c = rgb.at<cv::Vec3b>(y, x);
        ASSERT_EQ(c[2], small(x, y).r);
        ASSERT_EQ(c[1], small(x, y).g);
        ASSERT_EQ(c[0], small(x, y).b);
      }
    // groundtruth: timestamp tx ty tz qx qy qz qw, the given pose.
    ASSERT_EQ(gt[i].size(), 8u);
    const Eigen::Quaterniond q(std::stod(gt[i][7]), std::stod(gt[i][4]), std::stod(gt[i][5]),
                               std::stod(gt[i][6]));
    EXPECT_TRUE(q.toRotationMatrix().isApprox(f.T_world_cam_given->linear(), 1e-6));
    EXPECT_NEAR(std::stod(gt[i][1]), f.T_world_cam_given->translation().x(), 1e-8);
  }
  // Frame 0 is diag(1, -1, -1): a half turn about x, quaternion (qx, qy, qz, qw) = (+-1, 0, 0, 0).
  EXPECT_NEAR(std::abs(std::stod(gt[0][4])), 1.0, 1e-6);
  EXPECT_NEAR(std::stod(gt[0][7]), 0.0, 1e-6);

  const auto calib = dataLines(dir + "/camera_intrinsics.txt");
  ASSERT_EQ(calib.size(), 2u);
  ASSERT_EQ(calib[0].size(), 4u);
  EXPECT_NEAR(std::stod(calib[0][0]), 191.216976, 1e-4);
  EXPECT_NEAR(std::stod(calib[0][1]), 191.216976, 1e-4);
  EXPECT_NEAR(std::stod(calib[0][2]), 95.798633, 1e-4);
  EXPECT_NEAR(std::stod(calib[0][3]), 129.382145, 1e-4);
  EXPECT_EQ(calib[1], std::vector<std::string>(5, "0.000000"));

  // No temporary files are left behind.
  for (const auto& e : fs::recursive_directory_iterator(dir))
    EXPECT_EQ(e.path().string().find(".tmp"), std::string::npos) << e.path();
}

// A source whose frame `bad` cannot be read, as a damaged capture would be.
class FailingSource : public FrameSource {
 public:
  FailingSource(const FrameSource& inner, int bad) : inner_(inner), bad_(bad) {}
  int size() const override { return 3; }
  RgbdFrame load(int index) const override {
    if (index == bad_) throw Error("frame " + std::to_string(index) + " is damaged");
    return inner_.load(index);
  }
  Intrinsics depthIntrinsics() const override { return inner_.depthIntrinsics(); }
  std::string description() const override { return "failing source"; }

 private:
  const FrameSource& inner_;
  int bad_;
};

TEST(TumWriter, ReplacesTheFolderOnlyOnceEveryFileIsWritten) {
  VF_REQUIRE_DATA(r3d, "record3d_dance_head200.r3d");
  Record3dCapture cap(r3d);
  const std::string dir = test::tempDir("tum_writer_replace") + "/out";
  fs::create_directories(dir);
  std::ofstream(dir + "/keep.txt") << "the previous output";
  // A read error half-way: the old folder stays as it was and no temporary is left.
  EXPECT_THROW(writeTumFolder(FailingSource(cap, 1), dir), Error);
  EXPECT_TRUE(fs::exists(dir + "/keep.txt"));
  EXPECT_FALSE(fs::exists(dir + "/depth.txt"));
  for (const auto& e : fs::directory_iterator(fs::path(dir).parent_path()))
    EXPECT_EQ(e.path().filename().string().find(".tmp"), std::string::npos) << e.path();
  // A complete write replaces the folder as a whole.
  TumWriteOptions options;
  options.max_frames = 1;
  EXPECT_EQ(writeTumFolder(cap, dir, options).frames, 1);
  EXPECT_FALSE(fs::exists(dir + "/keep.txt"));
  EXPECT_EQ(dataLines(dir + "/depth.txt").size(), 1u);
}

TEST(TumWriter, TimestampsHaveSixDecimals) {
  EXPECT_EQ(tumTimestampString(1305031102.175304), "1305031102.175304");
  EXPECT_EQ(tumTimestampString(0.0), "0.000000");
}

}  // namespace
}  // namespace vf
