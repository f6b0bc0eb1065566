// The ring corridor (issues 36 and 41): a walk of more than 30 m that comes back to its start
// and sees the same walls on both passes, Kinect v1 depth in disparity steps with a fixed
// per-pixel bias, and the stress variants (gaps, blanks, a close-up of one plain wall). Small
// images and a few frames each: CI has 2 cores.
#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <filesystem>
#include <set>
#include <string>
#include <unistd.h>

#include "core/error.h"
#include "corridor_geometry.h"
#include "corridor_path.h"
#include "io/tum_dataset.h"
#include "io/tum_writer.h"
#include "room_evaluation.h"
#include "room_mesh.h"
#include "room_source.h"
#include "view_conditioning.h"

namespace vf::synth {
namespace {

namespace fs = std::filesystem;

RoomScanOptions smallCorridor(int frames, int width = 64, int height = 48) {
  RoomScanOptions o = scanDefaults(Scene::kCorridor);
  o.frames = frames;
  o.width = width;
  o.height = height;
  return o;
}

bool sameImages(const RgbdFrame& a, const RgbdFrame& b) {
  if (a.depth.width() != b.depth.width() || a.depth.height() != b.depth.height()) return false;
  for (int y = 0; y < a.depth.height(); ++y)
    for (int x = 0; x < a.depth.width(); ++x) {
      if (a.depth(x, y) != b.depth(x, y)) return false;
      const Rgb8 ca = a.color(x, y), cb = b.color(x, y);
      if (ca.r != cb.r || ca.g != cb.g || ca.b != cb.b) return false;
    }
  return true;
}

int framesWithDepth(const RgbdFrame& f) {
  int n = 0;
  for (int y = 0; y < f.depth.height(); ++y)
    for (int x = 0; x < f.depth.width(); ++x) n += f.depth(x, y) > 0;
  return n;
}

TEST(SyntheticCorridor, WalkGoesMoreThan30MetresRoundTheLoopAndComesBackToItsStart) {
  const Trajectory path = corridorPath(kCorridorDefaultFrames);
  const PathStats s = pathStats(path);
  EXPECT_GE(s.length_m, 30.0);
  EXPECT_LE(s.length_m, 45.0);
  EXPECT_NEAR(s.turn_deg, 360.0, 20.0) << "once round, ending on the leg it started on";
  EXPECT_GT(s.length_m, corridorLoopLength_m() + 4.0) << "and on along it";
  EXPECT_LE(s.max_speed_m_s, 1.1) << "walking speed";
  EXPECT_GE(s.length_m / (path.back().timestamp - path.front().timestamp), 0.8);
  EXPECT_LT(s.max_turn_rate_deg_s, 90.0);
  EXPECT_GT(s.min_height_m, 1.35);
  EXPECT_LT(s.max_height_m, 1.55);

  // Back at the start: some frame of the second pass stands within a few cm of frame 0.
  const int loop_frame = int(std::lround(corridorLoopTime_s() * kFrameRateHz));
  ASSERT_LT(loop_frame + 30, kCorridorDefaultFrames);
  double closest = 1e9;
  int closest_frame = -1;
  for (int i = loop_frame - 30; i <= loop_frame + 30; ++i) {
    const double d = (path[size_t(i)].T_world_cam.translation() - path[0].T_world_cam.translation()).norm();
    if (d < closest) closest = d, closest_frame = i;
  }
  EXPECT_LT(closest, 0.03) << "frame " << closest_frame;
  EXPECT_NEAR(closest_frame, loop_frame, 1);

  // Always in the corridor, clear of every solid.
  const Room corridor = makeCorridor();
  for (const StampedPose& p : path)
    ASSERT_GT(corridor.distanceToSurface(p.T_world_cam.translation().cast<float>()), 0.4f) << p.timestamp;
}

// Walks 1.. carry the camera differently along the same loop: as far from every solid, as slow
// to turn, back at the start at the same frame, but looking elsewhere.
TEST(SyntheticCorridor, OtherWalksKeepTheLoopAndLookElsewhere) {
  const Room corridor = makeCorridor();
  const Trajectory base = corridorPath(kCorridorDefaultFrames);
  const int loop_frame = int(std::lround(corridorLoopTime_s() * kFrameRateHz));
  for (uint64_t walk : {1, 2, 3, 4, 5}) {
    SCOPED_TRACE("walk " + std::to_string(walk));
    const Trajectory path = corridorPath(kCorridorDefaultFrames, std::nullopt, walk);
    ASSERT_EQ(path.size(), base.size());
    const PathStats s = pathStats(path);
    EXPECT_LE(s.max_speed_m_s, 1.1);
    EXPECT_LT(s.max_turn_rate_deg_s, 90.0);
    EXPECT_GT(s.min_height_m, 1.35);
    EXPECT_LT(s.max_height_m, 1.55);
    EXPECT_LT((path[size_t(loop_frame)].T_world_cam.translation() - path[0].T_world_cam.translation()).norm(), 0.05);
    double largest_yaw_difference_deg = 0;
    for (size_t i = 0; i < path.size(); ++i) {
      ASSERT_GT(corridor.distanceToSurface(path[i].T_world_cam.translation().cast<float>()), 0.4f) << i;
      const Eigen::Vector3d a = base[i].T_world_cam.linear().col(2), b = path[i].T_world_cam.linear().col(2);
      const double yaw_a = std::atan2(a.y(), a.x()), yaw_b = std::atan2(b.y(), b.x());
      largest_yaw_difference_deg =
          std::max(largest_yaw_difference_deg, std::abs(std::remainder(yaw_a - yaw_b, 2 * M_PI)) * 180.0 / M_PI);
    }
    EXPECT_GT(largest_yaw_difference_deg, 20.0) << "it looks elsewhere than walk 0";
  }
  // A walk is a function of its number: generated twice, it is the same.
  const Trajectory again = corridorPath(60, std::nullopt, 3), once = corridorPath(60, std::nullopt, 3);
  for (size_t i = 0; i < once.size(); ++i) EXPECT_TRUE(once[i].T_world_cam.isApprox(again[i].T_world_cam)) << i;
}

TEST(SyntheticCorridor, AWalkNumberNeedsTheCorridor) {
  RoomScanOptions o = scanDefaults(Scene::kRoom);
  o.walk = 2;
  try {
    RoomScanSource source(o);
    FAIL() << "a walk number was accepted for the room";
  } catch (const Error& e) {
    EXPECT_NE(std::string(e.what()).find("--walk"), std::string::npos) << e.what();
  }
}

TEST(SyntheticCorridor, BothPassesSeeTheWallsRoundTheStart) {
  const Room corridor = makeCorridor();
  const SurfaceSamples samples = sampleSurface(corridor, 0.05f);
  const Trajectory path = corridorPath(kCorridorDefaultFrames);
  const int loop_frame = int(std::lround(corridorLoopTime_s() * kFrameRateHz));
  Trajectory first, second;
  for (int i = 0; i < kCorridorDefaultFrames; i += 6) (i < loop_frame ? first : second).push_back(path[size_t(i)]);
  const Intrinsics k = kinectIntrinsics(160, 120);
  const std::vector<uint8_t> seen1 = markSeen(corridor, samples, first, k), seen2 = markSeen(corridor, samples, second, k);
  // Wall surface (vertical faces: walls, doors, frames) seen by both passes, and the share of the
  // second pass's that the first saw too.
  size_t both = 0, only_second = 0;
  for (size_t i = 0; i < samples.size(); ++i) {
    if (std::abs(samples.normals[i].z()) > 0.5f || !seen2[i]) continue;
    (seen1[i] ? both : only_second) += 1;
  }
  const double both_m2 = double(both) * 0.05 * 0.05;
  EXPECT_GT(both_m2, 20.0) << "walls seen on both passes";
  EXPECT_GT(double(both) / double(both + only_second), 0.9) << "the second pass goes over the first's walls";
}

// A view of a flat surface at z everywhere: what the sensor model turns it into.
CleanView flatView(int width, int height, float z) {
  CleanView v;
  v.depth.resize(width, height, z);
  v.color.resize(width, height, Rgb8{128, 128, 128, 255});
  v.cos_incidence.assign(size_t(width * height), 1.f);
  v.primitive.assign(size_t(width * height), int16_t(0));
  return v;
}

TEST(SyntheticCorridor, KinectDepthComesInDisparityStepsOf2p85e3ZSquared) {
  SensorModel sensor = kinectV1Sensor();
  sensor.dropout_fraction = 0;
  for (float z : {1.f, 2.f, 3.f}) {
    std::set<float> levels;
    const CleanView view = flatView(64, 48, z);
    for (int frame = 0; frame < 10; ++frame) {
      RgbdFrame out;
      applySensor(view, sensor, 1, frame, out);
      for (int y = 0; y < 48; ++y)
        for (int x = 0; x < 64; ++x) levels.insert(out.depth(x, y));
    }
    ASSERT_GE(levels.size(), 3u) << z;
    // Each reading is a disparity level 1 / (k 2.85e-3), written in the TUM PNG's 0.2 mm steps.
    for (float d : levels) {
      const double level = 1.0 / (std::round(1.0 / (d * 2.85e-3)) * 2.85e-3);
      EXPECT_NEAR(d, level, 1e-4 + 1e-6) << "z " << z;
    }
    // Neighbouring readings are one step apart: 2.85e-3 z^2 (2.85 mm, 11.4 mm, 25.7 mm).
    const std::vector<float> sorted(levels.begin(), levels.end());
    double smallest = 1e9;
    for (size_t i = 1; i < sorted.size(); ++i) smallest = std::min(smallest, double(sorted[i] - sorted[i - 1]));
    EXPECT_NEAR(smallest, 2.85e-3 * z * z, 0.04 * 2.85e-3 * z * z + 2e-4) << "z " << z;
  }
}

TEST(SyntheticCorridor, DepthBiasIsTheSameForAPixelInEveryFrameAndForEverySeed) {
  SensorModel sensor = kinectV1Sensor();
  sensor.dropout_fraction = 0;
  const int w = 64, h = 48, block = 8;
  const float z = 2.f;
  const CleanView view = flatView(w, h, z);
  // Mean relative error per 8x8 block over two disjoint sets of 24 frames (other seeds, other
  // frame numbers): the noise averages out, a fixed bias does not.
  auto blockMeans = [&](uint64_t seed, int first_frame) {
    std::vector<double> sum(size_t((w / block) * (h / block)), 0.0);
    for (int frame = first_frame; frame < first_frame + 24; ++frame) {
      RgbdFrame out;
      applySensor(view, sensor, seed, frame, out);
      for (int y = 0; y < h; ++y)
        for (int x = 0; x < w; ++x) sum[size_t((y / block) * (w / block) + x / block)] += (out.depth(x, y) - z) / z;
    }
    for (double& s : sum) s /= 24.0 * block * block;
    return sum;
  };
  const std::vector<double> a = blockMeans(1, 0), b = blockMeans(2, 100);
  double lo = 1, hi = -1;
  for (size_t i = 0; i < a.size(); ++i) {
    double expected = 0;
    const int bx = int(i) % (w / block), by = int(i) / (w / block);
    for (int y = by * block; y < (by + 1) * block; ++y)
      for (int x = bx * block; x < (bx + 1) * block; ++x) expected += sensor.bias_per_m * depthBiasPattern(x, y, w, h);
    expected /= block * block;
    EXPECT_NEAR(a[i], expected, 4e-4) << "block " << i;
    EXPECT_NEAR(b[i], a[i], 4e-4) << "block " << i;
    lo = std::min(lo, a[i]);
    hi = std::max(hi, a[i]);
  }
  EXPECT_GT(hi - lo, 3e-3) << "a few millimetres per metre across the image";
  EXPECT_LT(std::max(hi, -lo), 8e-3);
  EXPECT_EQ(depthBiasPattern(10, 20, w, h), depthBiasPattern(10, 20, w, h));
}

TEST(SyntheticCorridor, GapLeavesFramesOutAndBlankWritesEmptyOnesWithTheWalkTimestamps) {
  const RoomScanSource plain(smallCorridor(20));
  RoomScanOptions o = smallCorridor(20);
  o.gaps = {{5, 3}};
  o.blanks = {{11, 2}};
  const RoomScanSource stressed(o);
  ASSERT_EQ(stressed.size(), 17);
  ASSERT_EQ(stressed.groundTruth().size(), 17u);
  EXPECT_EQ(stressed.depthPoses().size(), 15u);
  const int walk_of[] = {0, 1, 2, 3, 4, 8, 9, 10, 11, 12, 13};
  for (int i = 0; i < 11; ++i) {
    ASSERT_EQ(stressed.walkIndex(i), walk_of[i]);
    EXPECT_DOUBLE_EQ(stressed.groundTruth()[size_t(i)].timestamp, frameTimestamp(walk_of[i]));
  }
  // Kept frames are the plain walk's, pixel for pixel; blanked ones have nothing.
  for (int i : {4, 5, 7, 10}) {
    const RgbdFrame f = stressed.load(i);
    EXPECT_DOUBLE_EQ(f.timestamp, frameTimestamp(walk_of[i])) << i;
    EXPECT_TRUE(sameImages(f, plain.load(walk_of[i]))) << i;
    EXPECT_GT(framesWithDepth(f), 64 * 48 / 2) << i;
  }
  for (int i : {8, 9}) {
    const RgbdFrame f = stressed.load(i);
    EXPECT_EQ(framesWithDepth(f), 0) << i;
    EXPECT_EQ(f.color(30, 20).r + f.color(30, 20).g + f.color(5, 40).b, 0) << i;
    ASSERT_TRUE(f.T_world_cam_given.has_value());
    EXPECT_TRUE(f.T_world_cam_given->isApprox(plain.groundTruth()[size_t(walk_of[i])].T_world_cam, 1e-12));
  }

  // Written and read back: the gap shows in the timestamps, the blank frames read no depth.
  const fs::path dir = fs::temp_directory_path() / ("vf_synth_corridor_" + std::to_string(::getpid()));
  fs::remove_all(dir);
  writeTumFolder(stressed, dir.string());
  const TumDataset tum(dir.string());
  ASSERT_EQ(tum.size(), 17);
  EXPECT_NEAR(tum.load(5).timestamp - tum.load(4).timestamp, 4.0 / 30.0, 1e-5);
  EXPECT_EQ(framesWithDepth(tum.load(8)), 0);
  EXPECT_TRUE(sameImages(tum.load(10), stressed.load(10)));
  EXPECT_EQ(tum.groundTruth().size(), 17u);
  fs::remove_all(dir);
}

void expectError(const std::function<void()>& f, const std::string& part) {
  try {
    f();
    ADD_FAILURE() << "no error; expected one saying '" << part << "'";
  } catch (const Error& e) {
    EXPECT_NE(std::string(e.what()).find(part), std::string::npos) << e.what();
  }
}

TEST(SyntheticCorridor, RunsThatCannotBeMadeAreRefusedByName) {
  const FrameRange r = parseFrameRange("300:60", "--gap");
  EXPECT_EQ(r.from, 300);
  EXPECT_EQ(r.count, 60);
  for (const char* bad : {"300", "300:0", "-1:5", "3:4x", ":5", "a:b"})
    expectError([&] { parseFrameRange(bad, "--gap"); }, std::string("--gap '") + bad + "': expected FROM:COUNT");
  RoomScanOptions o = smallCorridor(40);
  o.gaps = {{38, 5}};
  expectError([&] { RoomScanSource s(o); }, "--gap 38:5: reaches frame 42, but the walk has frames 0..39");
  o.gaps = {{10, 5}};
  o.blanks = {{14, 3}};
  expectError([&] { RoomScanSource s(o); }, "--gap 10:5 and --blank 14:3 share frames");
  o.blanks.clear();
  o.gaps = {{0, 40}};
  expectError([&] { RoomScanSource s(o); }, "leaves no frame");
  RoomScanOptions room = scanDefaults(Scene::kRoom);
  room.close_wall = FrameRange{10, 90};
  expectError([&] { RoomScanSource s(room); }, "--close-wall: only the corridor");
  expectError([] { parseScene("hall"); }, "scene 'hall': expected room or corridor");
}

TEST(SyntheticCorridor, CloseWallFramesSeeOnlyOnePlainWallUpClose) {
  const FrameRange run = kSuggestedCloseWall;
  const Room corridor = makeCorridor();
  const Trajectory plain = corridorPath(run.end() + 10), close = corridorPath(run.end() + 10, run);
  const Intrinsics k = kinectIntrinsics(80, 60);
  int full = 0;
  for (int i = run.from - 5; i < run.end() + 5; ++i) {
    const Pose& T = close[size_t(i)].T_world_cam;
    if (!run.contains(i) || i == run.from || i == run.end() - 1) {
      EXPECT_TRUE(T.isApprox(plain[size_t(i)].T_world_cam, 1e-15)) << "frame " << i << " is the plain walk's";
      continue;
    }
    if (closeWallBlend(run, i) < 1.0) continue;
    ++full;
    const CleanView view = renderClean(corridor, k, T);
    const int wall = view.primitive[0];
    ASSERT_GE(wall, 0);
    EXPECT_EQ(corridor.primitives[size_t(wall)].name.rfind("wall_north_outer", 0), 0u) << corridor.primitives[size_t(wall)].name;
    for (size_t p = 0; p < view.primitive.size(); ++p) ASSERT_EQ(view.primitive[p], wall) << "frame " << i;
    for (int y = 0; y < k.height; ++y)
      for (int x = 0; x < k.width; ++x) {
        ASSERT_GT(view.depth(x, y), 0.6f);
        ASSERT_LT(view.depth(x, y), 1.0f);
      }
    EXPECT_EQ(weakDirections(icpConditioning(corridor, view, k, T)), 3) << "frame " << i;
  }
  EXPECT_GE(full, 30) << "a second or more of nothing but the wall";
}

TEST(SyntheticCorridor, MostViewsPinTheCameraAlongTheCorridorButSomeStretchesDoNot) {
  const RoomScanSource source(smallCorridor(kCorridorDefaultFrames, 80, 60));
  const Intrinsics k = source.depthIntrinsics();
  int weak = 0, views = 0;
  for (int i = 0; i < kCorridorDefaultFrames; i += 15) {
    const int n = weakDirections(icpConditioning(source.room(), source.cleanView(i), k, source.walk()[size_t(i)].T_world_cam));
    EXPECT_LE(n, 1) << "frame " << i << ": a corridor view leaves at most the direction along it";
    weak += n > 0;
    ++views;
  }
  EXPECT_GT(weak, 0.05 * views) << "featureless stretches";
  EXPECT_LT(weak, 0.35 * views) << "geometry pins the camera most of the time";
}

TEST(SyntheticCorridor, GroundTruthMeshScoresCompleteWithNoErrorAndADoubledWallShowsInThe90thPercentile) {
  const Room corridor = makeCorridor();
  const SurfaceSamples samples = sampleSurface(corridor, 0.05f);
  Trajectory some;
  const Trajectory path = corridorPath(kCorridorDefaultFrames);
  for (size_t i = 0; i < path.size(); i += 20) some.push_back(path[i]);
  const std::vector<uint8_t> seen = markSeen(corridor, samples, some, kinectIntrinsics(80, 60));
  const TriangleMesh mesh = groundTruthMesh(corridor, 0.25f);
  const SurfaceScores s = scoreReconstruction(corridor, samples, seen, mesh, 0.03f);
  EXPECT_DOUBLE_EQ(s.completion, 1.0);
  EXPECT_LT(s.accuracy_p90_m, 1e-4);

  // Patches 5 mm above the floor in the middle of the south leg, and some 4 cm above it: the
  // 90th percentile is 5 mm while at least 90 % of the vertices are at 5 mm, 4 cm once fewer are.
  auto patches = [](int near, int far) {
    TriangleMesh m;
    for (int i = 0; i < near + far; ++i) {
      const float x = 4.f + 0.02f * float(i), z = i < near ? 0.005f : 0.04f;
      const int32_t v = int32_t(m.positions.size());
      m.positions.push_back({x, 1.f, z});
      m.positions.push_back({x + 0.01f, 1.f, z});
      m.positions.push_back({x, 1.01f, z});
      m.triangles.push_back({v, v + 1, v + 2});
    }
    return m;
  };
  EXPECT_NEAR(scoreReconstruction(corridor, samples, seen, patches(90, 10), 0.03f).accuracy_p90_m, 0.005, 1e-6);
  EXPECT_NEAR(scoreReconstruction(corridor, samples, seen, patches(89, 11), 0.03f).accuracy_p90_m, 0.04, 1e-6);
}

}  // namespace
}  // namespace vf::synth
