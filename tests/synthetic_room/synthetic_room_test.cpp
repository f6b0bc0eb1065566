// The synthetic room scan: same seed same frames, depth equal to the known surface, Kinect
// noise with the stated sigma(z), a path that turns fully at walking speed with enough to track
// in every frame, and a completion metric that gives 100 % for the ground truth itself.
#include <gtest/gtest.h>

#include <cmath>
#include <filesystem>
#include <map>

#include "io/tum_dataset.h"
#include "io/tum_writer.h"
#include "room_evaluation.h"
#include "room_mesh.h"
#include "room_source.h"
#include "view_conditioning.h"

namespace vf::synth {
namespace {

namespace fs = std::filesystem;

RoomScanOptions smallScan(int width, int height, bool noise, uint64_t seed = 1) {
  RoomScanOptions o;
  o.width = width;
  o.height = height;
  o.sensor.noise = noise;
  o.seed = seed;
  return o;
}

Vec3 worldPoint(const Intrinsics& k, const Pose& T, int x, int y, float z) {
  const Eigen::Vector3d p = T * Eigen::Vector3d((x - k.cx) / k.fx * z, (y - k.cy) / k.fy * z, z);
  return p.cast<float>();
}

bool sameImages(const RgbdFrame& a, const RgbdFrame& b) {
  for (int y = 0; y < a.depth.height(); ++y)
    for (int x = 0; x < a.depth.width(); ++x) {
      if (a.depth(x, y) != b.depth(x, y)) return false;
      const Rgb8 ca = a.color(x, y), cb = b.color(x, y);
      if (ca.r != cb.r || ca.g != cb.g || ca.b != cb.b) return false;
    }
  return true;
}

TEST(SyntheticRoom, SameSeedGivesTheSameFramesInAnyOrderAndAnotherSeedOthers) {
  const RoomScanSource a(smallScan(96, 72, true, 7)), b(smallScan(96, 72, true, 7)), c(smallScan(96, 72, true, 8));
  const RgbdFrame a5 = a.load(5), a2 = a.load(2);
  EXPECT_TRUE(sameImages(b.load(2), a2));
  EXPECT_TRUE(sameImages(b.load(5), a5));
  EXPECT_TRUE(sameImages(a.load(5), a5));
  EXPECT_FALSE(sameImages(c.load(5), a5));
  EXPECT_DOUBLE_EQ(a5.timestamp, 1.0 + 5.0 / 30.0);
  ASSERT_TRUE(a5.T_world_cam_given.has_value());
  EXPECT_TRUE(a5.T_world_cam_given->isApprox(a.groundTruth()[5].T_world_cam, 1e-12));
}

TEST(SyntheticRoom, CleanDepthLiesOnTheKnownSurfaceAndIsItsFirstHit) {
  const RoomScanSource source(smallScan(160, 120, false));
  const Intrinsics k = source.depthIntrinsics();
  const Room& room = source.room();
  int checked = 0;
  for (int index : {0, 77, 150, 233, 299}) {
    const RgbdFrame frame = source.load(index);
    const Pose T = *frame.T_world_cam_given;
    const Vec3 origin = T.translation().cast<float>();
    for (int y = 1; y < k.height; y += 9)
      for (int x = 2; x < k.width; x += 11) {
        const float z = frame.depth(x, y);
        ASSERT_GT(z, 0.f) << "every ray inside the room hits a surface";
        const Vec3 p = worldPoint(k, T, x, y, z);
        EXPECT_LT(room.distanceToSurface(p), 1e-4f) << "frame " << index << " pixel " << x << "," << y;
        // Sphere tracing with the exact distance function finds the first surface on the ray on
        // its own: the renderer must not have missed a nearer one.
        const Vec3 dir = (p - origin).normalized();
        float t = 0;
        for (int step = 0; step < 5000; ++step) {
          const float d = room.distanceToSurface(origin + t * dir);
          if (d < 2e-5f) break;
          t += d;
        }
        EXPECT_NEAR(t, (p - origin).norm(), 2e-3f) << "frame " << index << " pixel " << x << "," << y;
        ++checked;
      }
  }
  EXPECT_GT(checked, 700);

  // Looking straight up from the middle of the room every pixel sees the ceiling, 2.6 - 1.5 m away.
  Pose up = Pose::Identity();  // camera z (forward) = world z (up)
  up.translation() = Eigen::Vector3d(4.0, 3.0, 1.5);
  const CleanView view = renderClean(room, k, up);
  for (int y = 0; y < k.height; ++y)
    for (int x = 0; x < k.width; ++x) ASSERT_NEAR(view.depth(x, y), 1.1f, 1e-5f) << x << "," << y;
}

TEST(SyntheticRoom, DepthNoiseFollowsTheKinectSigmaAndReadingsGoMissingWhereTheSensorFails) {
  const RoomScanSource noisy(smallScan(160, 120, true, 3)), clean(smallScan(160, 120, false));
  struct Bin {
    double sum = 0, sum2 = 0, expected_var = 0;
    int n = 0;
  };
  std::map<int, Bin> bins;  // by clean depth, 0.5 m wide
  int usable = 0, dropped = 0, grazing = 0, grazing_read = 0, far = 0, far_read = 0;
  const float min_cos = std::cos(75.f * float(M_PI) / 180.f), step = 1.f / 5000.f;
  for (int index = 0; index < 300; index += 20) {
    const RgbdFrame n = noisy.load(index);
    const CleanView c = clean.cleanView(index);
    for (int y = 0; y < c.depth.height(); ++y)
      for (int x = 0; x < c.depth.width(); ++x) {
        const float z = c.depth(x, y), zn = n.depth(x, y);
        const float cos_i = c.cos_incidence[size_t(y * c.depth.width() + x)];
        if (z > 4.5f) {
          ++far;
          far_read += zn > 0;
          continue;
        }
        if (cos_i < min_cos) {
          ++grazing;
          grazing_read += zn > 0;
          continue;
        }
        if (z < 0.4f) continue;
        ++usable;
        if (zn == 0) {
          ++dropped;
          continue;
        }
        EXPECT_NEAR(std::round(zn / step) * step, zn, 1e-7f) << "depth comes in 1/5000 m steps";
        Bin& b = bins[int(z / 0.5f)];
        const double r = double(zn) - double(z);
        b.sum += r;
        b.sum2 += r * r;
        b.expected_var += double(axialSigma(z)) * axialSigma(z) + double(step) * step / 12.0;
        ++b.n;
      }
  }
  int bins_checked = 0;
  for (const auto& [bin, b] : bins) {
    if (b.n < 1000) continue;
    const double mean = b.sum / b.n, sigma = std::sqrt(b.sum2 / b.n - mean * mean);
    const double expected = std::sqrt(b.expected_var / b.n);
    EXPECT_NEAR(sigma / expected, 1.0, 0.1) << "depth " << bin * 0.5 << "-" << bin * 0.5 + 0.5 << " m, " << b.n << " pixels";
    EXPECT_LT(std::abs(mean), 4 * expected / std::sqrt(double(b.n))) << "noise is unbiased";
    ++bins_checked;
  }
  EXPECT_GE(bins_checked, 5) << "the scan covers 1-4 m";
  EXPECT_GT(grazing, 100);
  EXPECT_EQ(grazing_read, 0) << "no reading beyond 75 degrees of incidence";
  EXPECT_EQ(far_read, 0) << "no reading beyond 4.5 m (" << far << " pixels)";
  const double dropout = double(dropped) / usable;
  EXPECT_GT(dropout, 0.002);
  EXPECT_LT(dropout, 0.007);
}

TEST(SyntheticRoom, PathTurnsFullyAtWalkingSpeedWithEnoughToTrackInEveryFrame) {
  const PathStats s = pathStats(cameraPath(kDefaultFrames));
  EXPECT_GE(s.turn_deg, 360.0);
  EXPECT_LT(s.turn_deg, 400.0);
  EXPECT_GT(s.length_m, 5.0);
  EXPECT_LT(s.max_speed_m_s, 1.0);
  EXPECT_LT(s.max_turn_rate_deg_s, 60.0);
  EXPECT_GT(s.min_height_m, 1.2);
  EXPECT_LT(s.max_height_m, 1.7);

  const RoomScanSource source(smallScan(80, 60, false));
  const Intrinsics k = source.depthIntrinsics();
  double worst_constraint = 1, worst_share = 1;
  for (int index = 0; index < kDefaultFrames; index += 10) {
    const CleanView view = source.cleanView(index);
    int in_range = 0;
    for (int y = 0; y < k.height; ++y)
      for (int x = 0; x < k.width; ++x) in_range += view.depth(x, y) >= 0.4f && view.depth(x, y) <= 4.f;
    worst_share = std::min(worst_share, double(in_range) / (k.width * k.height));
    // Smallest over largest eigenvalue of the point-to-plane ICP normal matrix (view_conditioning.h).
    worst_constraint =
        std::min(worst_constraint, icpConditioning(source.room(), view, k, source.groundTruth()[size_t(index)].T_world_cam)(0));
  }
  EXPECT_GT(worst_share, 0.85) << "pixels within the fusion's 0.4-4 m in the worst frame";
  // A view of the ceiling or the floor alone gives 0; the worst frame of the path gives 0.005.
  EXPECT_GT(worst_constraint, 1e-3) << "every frame constrains all six degrees of freedom";
}

TEST(SyntheticRoom, TumFolderRoundTripsTheFramesExactly) {
  RoomScanOptions o = smallScan(64, 48, true, 5);
  o.frames = 3;
  const RoomScanSource source(o);
  const fs::path dir = fs::temp_directory_path() / ("vf_synth_room_" + std::to_string(::getpid()));
  fs::remove_all(dir);
  writeTumFolder(source, dir.string());
  const TumDataset tum(dir.string());
  ASSERT_EQ(tum.size(), 3);
  const Intrinsics k = tum.depthIntrinsics(), e = source.depthIntrinsics();
  EXPECT_FLOAT_EQ(k.fx, e.fx);
  EXPECT_FLOAT_EQ(k.cy, e.cy);
  for (int i = 0; i < 3; ++i) {
    const RgbdFrame a = source.load(i), b = tum.load(i);
    EXPECT_TRUE(sameImages(a, b)) << "frame " << i;
    ASSERT_TRUE(b.T_world_cam_given.has_value());
    EXPECT_TRUE(b.T_world_cam_given->isApprox(*a.T_world_cam_given, 1e-8));
  }
  fs::remove_all(dir);
}

struct CompletionFixture : ::testing::Test {
  static void SetUpTestSuite() {
    room = new Room(makeRoom());
    samples = new SurfaceSamples(sampleSurface(*room, 0.03f));
    Trajectory every_tenth;
    const Trajectory path = cameraPath(kDefaultFrames);
    for (size_t i = 0; i < path.size(); i += 10) every_tenth.push_back(path[i]);
    seen = new std::vector<uint8_t>(markSeen(*room, *samples, every_tenth, kinectIntrinsics(160, 120)));
    mesh = new TriangleMesh(groundTruthMesh(*room, 0.2f, &triangle_primitive));
  }
  static void TearDownTestSuite() {
    delete room;
    delete samples;
    delete seen;
    delete mesh;
  }
  static Room* room;
  static SurfaceSamples* samples;
  static std::vector<uint8_t>* seen;
  static TriangleMesh* mesh;
  static std::vector<int> triangle_primitive;
};
Room* CompletionFixture::room = nullptr;
SurfaceSamples* CompletionFixture::samples = nullptr;
std::vector<uint8_t>* CompletionFixture::seen = nullptr;
TriangleMesh* CompletionFixture::mesh = nullptr;
std::vector<int> CompletionFixture::triangle_primitive;

TEST_F(CompletionFixture, SamplesLieOnTheSurfaceAndThePathSeesPartOfIt) {
  size_t n_seen = 0;
  for (size_t i = 0; i < samples->size(); ++i) {
    ASSERT_LT(room->distanceToSurface(samples->points[i]), 1e-5f);
    n_seen += (*seen)[i];
  }
  const double share = double(n_seen) / double(samples->size());
  EXPECT_GT(share, 0.3) << "walls, floor and furniture";
  EXPECT_LT(share, 0.9) << "not the ceiling, nor behind the furniture";
  // No floor under the sideboard: hidden faces are not sampled.
  const Vec3 under_sideboard(3.8f, 0.2f, 0.f);
  for (size_t i = 0; i < samples->size(); ++i) ASSERT_GT((samples->points[i] - under_sideboard).norm(), 0.1f);
}

TEST_F(CompletionFixture, GroundTruthMeshIsCompleteAndExact) {
  const SurfaceScores s = scoreReconstruction(*room, *samples, *seen, *mesh, 0.03f);
  EXPECT_EQ(s.complete, s.seen);
  EXPECT_DOUBLE_EQ(s.completion, 1.0);
  EXPECT_LT(s.accuracy_mean_m, 1e-4);
  EXPECT_DOUBLE_EQ(s.precision, 1.0);
}

TEST_F(CompletionFixture, MeshWithoutThePartsOfOnePrimitiveMissesExactlyWhatIsFarFromTheRest) {
  for (const char* name : {"shell", "sofa_base", "table_ball"}) {
    const int gone = room->find(name);
    ASSERT_GE(gone, 0) << name;
    const SurfaceScores s = scoreReconstruction(*room, *samples, *seen, meshWithout(*mesh, triangle_primitive, gone), 0.03f);
    // Expected from the primitives: a seen point counts as long as another surface is within 3 cm.
    size_t expected = 0, n_seen = 0;
    for (size_t i = 0; i < samples->size(); ++i) {
      if (!(*seen)[i]) continue;
      ++n_seen;
      expected += room->distanceToSurfaceWithout(samples->points[i], gone) <= 0.03f;
    }
    EXPECT_NEAR(double(s.complete), double(expected), 0.001 * n_seen) << name;
    EXPECT_LT(s.completion, 1.0) << name;
  }
  // Without the shell (floor, ceiling, niche backs) about half of what was seen is gone.
  const SurfaceScores no_shell = scoreReconstruction(*room, *samples, *seen, meshWithout(*mesh, triangle_primitive, 0), 0.03f);
  EXPECT_LT(no_shell.completion, 0.8);
  EXPECT_GT(no_shell.completion, 0.3);
}

TEST_F(CompletionFixture, AlignmentBringsAFirstCameraFrameReconstructionIntoTheRoom) {
  // vdbfuse reconstructs in the first camera's frame: the estimate is the ground truth seen from there.
  const Trajectory gt = cameraPath(30);
  const Pose T_cam0_world = gt[0].T_world_cam.inverse();
  Trajectory estimate = gt;
  for (StampedPose& p : estimate) p.T_world_cam = T_cam0_world * p.T_world_cam;
  for (Alignment a : {Alignment::kFirstPose, Alignment::kAte}) {
    const Pose T = alignTo(estimate, gt, a);
    EXPECT_TRUE(T.isApprox(gt[0].T_world_cam, 1e-6));
  }
  const TriangleMesh in_camera = transformed(*mesh, T_cam0_world);
  const SurfaceScores s = scoreReconstruction(*room, *samples, *seen, transformed(in_camera, alignTo(estimate, gt, Alignment::kAte)), 0.03f);
  EXPECT_GT(s.completion, 0.9999);
}

}  // namespace
}  // namespace vf::synth
