#pragma once
// Small synthetic folders in the layouts of 7-Scenes, Replica, ScanNet and Redwood, written by
// the tests (never committed data). Every frame looks at a wall 2 m ahead in the world
// (z = 2), from poses that move and turn a little, so fusion with the given poses works.
#include <opencv2/imgcodecs.hpp>

#include <cstdio>
#include <filesystem>
#include <fstream>
#include <string>
#include <vector>

#include "core/pose.h"
#include "io/image_io.h"

namespace vf::test {

constexpr int kFixtureWidth = 64, kFixtureHeight = 48;
constexpr float kFixtureFx = 60.f, kFixtureFy = 60.f, kFixtureCx = 31.5f, kFixtureCy = 23.5f;
constexpr double kWallZ_m = 2.0;

inline std::vector<Pose> fixturePoses(int n) {
  std::vector<Pose> poses;
  for (int i = 0; i < n; ++i) {
    Pose p = Pose::Identity();
    p.linear() = Eigen::AngleAxisd(0.02 * i, Eigen::Vector3d(0.3, 1, 0.1).normalized()).toRotationMatrix();
    p.translation() = Eigen::Vector3d(0.5 + 0.01 * i, -0.2 + 0.005 * i, 0.1 + 0.003 * i);
    poses.push_back(p);
  }
  return poses;
}

// Depth (metres) of the wall z = kWallZ_m seen from `pose` with the fixture camera at w x h.
inline DepthImage wallDepth(const Pose& pose, int w = kFixtureWidth, int h = kFixtureHeight) {
  DepthImage d(w, h);
  const double sx = double(w) / kFixtureWidth, sy = double(h) / kFixtureHeight;
  for (int y = 0; y < h; ++y)
    for (int x = 0; x < w; ++x) {
      const Eigen::Vector3d ray((x - kFixtureCx * sx) / (kFixtureFx * sx), (y - kFixtureCy * sy) / (kFixtureFy * sy), 1);
      const Eigen::Vector3d dir = pose.linear() * ray;
      const double t = (kWallZ_m - pose.translation().z()) / dir.z();
      d(x, y) = float(t);  // ray has z = 1 in the camera: t is the depth
    }
  return d;
}

// Left half red, right half blue (w x h), as an 8-bit BGR image for OpenCV.
inline cv::Mat halvesImage(int w, int h) {
  cv::Mat m(h, w, CV_8UC3);
  for (int y = 0; y < h; ++y)
    for (int x = 0; x < w; ++x) m.at<cv::Vec3b>(y, x) = x < w / 2 ? cv::Vec3b(0, 0, 255) : cv::Vec3b(255, 0, 0);
  return m;
}

inline void writeColor(const std::string& path, int w, int h) {
  cv::imwrite(path, halvesImage(w, h), {cv::IMWRITE_JPEG_QUALITY, 100});
}

// Writes a 16-bit PNG of raw units (depth_m * units, rounded), raw values given where set.
inline void writeRawDepth(const std::string& path, const DepthImage& depth_m, double units) {
  cv::Mat m(depth_m.height(), depth_m.width(), CV_16UC1);
  for (int y = 0; y < depth_m.height(); ++y)
    for (int x = 0; x < depth_m.width(); ++x) m.at<uint16_t>(y, x) = uint16_t(std::lround(depth_m(x, y) * units));
  cv::imwrite(path, m);
}

inline std::string matrixText(const Pose& p, const char* row_end = "\n") {
  std::string out;
  char buf[64];
  for (int r = 0; r < 4; ++r) {
    for (int c = 0; c < 4; ++c) {
      std::snprintf(buf, sizeof buf, "%.17g%s", p.matrix()(r, c), c < 3 ? " " : "");
      out += buf;
    }
    out += row_end;
  }
  return out;
}

inline void writeText(const std::string& path, const std::string& text) { std::ofstream(path) << text; }

inline std::string sixDigits(int i) {
  char buf[16];
  std::snprintf(buf, sizeof buf, "%06d", i);
  return buf;
}

// 7-Scenes: depth in mm, 65535 in the top-left 4x4 pixels (no reading).
inline void writeSevenScenes(const std::string& dir, const std::vector<Pose>& poses, double scale = 1000,
                             bool intrinsics_file = true) {
  std::filesystem::create_directories(dir);
  if (intrinsics_file)
    writeText(dir + "/camera-intrinsics.txt", std::to_string(kFixtureFx) + " 0 " + std::to_string(kFixtureCx) + "\n0 " +
                                                  std::to_string(kFixtureFy) + " " + std::to_string(kFixtureCy) +
                                                  "\n0 0 1\n");
  for (size_t i = 0; i < poses.size(); ++i) {
    const std::string stem = dir + "/frame-" + sixDigits(int(i));
    DepthImage d = wallDepth(poses[i]);
    for (int y = 0; y < 4; ++y)
      for (int x = 0; x < 4; ++x) d(x, y) = float(65535 / scale);
    writeRawDepth(stem + ".depth.png", d, scale);
    writeColor(stem + ".color.jpg", kFixtureWidth, kFixtureHeight);
    writeText(stem + ".pose.txt", matrixText(poses[i]));
  }
}

// Replica: <dir>/scene/results/..., <dir>/scene/traj.txt, <dir>/cam_params.json; returns the
// scene folder.
inline std::string writeReplica(const std::string& dir, const std::vector<Pose>& poses) {
  const std::string scene = dir + "/scene";
  std::filesystem::create_directories(scene + "/results");
  writeText(dir + "/cam_params.json", "{\"camera\": {\"w\": 64, \"h\": 48, \"fx\": 60.0, \"fy\": 60.0, \"cx\": 31.5, "
                                      "\"cy\": 23.5, \"scale\": 6553.5}}");
  std::string traj;
  for (size_t i = 0; i < poses.size(); ++i) {
    writeRawDepth(scene + "/results/depth" + sixDigits(int(i)) + ".png", wallDepth(poses[i]), 6553.5);
    writeColor(scene + "/results/frame" + sixDigits(int(i)) + ".jpg", kFixtureWidth, kFixtureHeight);
    traj += matrixText(poses[i], " ");
    traj.back() = '\n';
  }
  writeText(scene + "/traj.txt", traj);
  return scene;
}

// ScanNet: colour at twice the depth size; pose/<lost_frame>.txt is all -inf (tracking lost).
inline void writeScanNet(const std::string& dir, const std::vector<Pose>& poses, int lost_frame = -1) {
  for (const char* sub : {"color", "depth", "pose", "intrinsic"}) std::filesystem::create_directories(dir + "/" + sub);
  char k[256];
  std::snprintf(k, sizeof k, "%g 0 %g 0\n0 %g %g 0\n0 0 1 0\n0 0 0 1\n", kFixtureFx, kFixtureCx, kFixtureFy, kFixtureCy);
  writeText(dir + "/intrinsic/intrinsic_depth.txt", k);
  for (size_t i = 0; i < poses.size(); ++i) {
    const std::string n = std::to_string(i);
    writeRawDepth(dir + "/depth/" + n + ".png", wallDepth(poses[i]), 1000);
    writeColor(dir + "/color/" + n + ".jpg", 2 * kFixtureWidth, 2 * kFixtureHeight);
    writeText(dir + "/pose/" + n + ".txt",
              int(i) == lost_frame ? "-inf -inf -inf -inf\n-inf -inf -inf -inf\n-inf -inf -inf -inf\n-inf -inf -inf -inf\n"
                                   : matrixText(poses[i]));
  }
}

// Redwood: color/ and depth/ (mm) named 000000.., a .log trajectory, Open3D intrinsics JSON.
inline void writeRedwood(const std::string& dir, const std::vector<Pose>& poses) {
  std::filesystem::create_directories(dir + "/color");
  std::filesystem::create_directories(dir + "/depth");
  writeText(dir + "/camera-intrinsics.json", "{\"width\": 64, \"height\": 48, \"intrinsic_matrix\": [60, 0, 0, 0, 60, 0, "
                                             "31.5, 23.5, 1]}");
  std::string log;
  for (size_t i = 0; i < poses.size(); ++i) {
    writeRawDepth(dir + "/depth/" + sixDigits(int(i)) + ".png", wallDepth(poses[i]), 1000);
    writeColor(dir + "/color/" + sixDigits(int(i)) + ".jpg", kFixtureWidth, kFixtureHeight);
    log += std::to_string(i) + " " + std::to_string(i) + " " + std::to_string(i + 1) + "\n" + matrixText(poses[i]);
  }
  writeText(dir + "/trajectory.log", log);
}

}  // namespace vf::test
