// Semantic fusion on synthetic scenes with known answers: class votes under label noise, the
// probabilistic vote's determinism, and dynamic classes kept out of the geometry.
#include <gtest/gtest.h>

#include <algorithm>
#include <cstdio>
#include <numeric>
#include <random>
#include <tuple>

#include "fusion/integrate_kernels.h"
#include "fusion/pipeline.h"
#include "synthetic_scene.h"

namespace vf {
namespace {

constexpr uint16_t kStatic = 1, kBall = 2;

// Class of the primitive a ray hits first: planes kStatic, spheres kBall, 0 = nothing.
uint16_t hitClass(const test::SyntheticScene& s, const Eigen::Vector3d& o, const Eigen::Vector3d& dir) {
  double best = std::numeric_limits<double>::infinity();
  uint16_t cls = 0;
  for (const test::Plane& p : s.planes) {
    const double denom = p.normal.dot(dir);
    if (std::abs(denom) < 1e-9) continue;
    const double t = (p.offset - p.normal.dot(o)) / denom;
    if (t > 1e-6 && t < best) best = t, cls = kStatic;
  }
  for (const test::Sphere& sp : s.spheres) {
    const Eigen::Vector3d oc = o - sp.center;
    const double b = oc.dot(dir), c = oc.squaredNorm() - sp.radius * sp.radius, disc = b * b - c;
    if (disc < 0) continue;
    const double t = -b - std::sqrt(disc);
    if (t > 1e-6 && t < best) best = t, cls = kBall;
  }
  return cls;
}

// Ground-truth label map of a rendered frame; `flip` of the surface pixels get the other class.
LabelImage renderLabels(const test::SyntheticScene& s, const Intrinsics& k, const Pose& T, double flip,
                        std::mt19937& rng) {
  LabelImage labels(k.width, k.height);
  std::uniform_real_distribution<double> u(0, 1);
  for (int y = 0; y < k.height; ++y)
    for (int x = 0; x < k.width; ++x) {
      const Eigen::Vector3d ray((x - k.cx) / k.fx, (y - k.cy) / k.fy, 1.0);
      uint16_t c = hitClass(s, T.translation(), T.linear() * ray.normalized());
      if (c != 0 && u(rng) < flip) c = c == kStatic ? kBall : kStatic;
      labels(x, y) = c;
    }
  return labels;
}

// Distance from p to the nearest sphere surface and to the nearest plane.
double sphereDistance(const test::SyntheticScene& s, const Eigen::Vector3d& p) {
  double d = 1e9;
  for (const test::Sphere& sp : s.spheres) d = std::min(d, std::abs((p - sp.center).norm() - sp.radius));
  return d;
}
double planeDistance(const test::SyntheticScene& s, const Eigen::Vector3d& p) {
  double d = 1e9;
  for (const test::Plane& pl : s.planes) d = std::min(d, std::abs(pl.normal.dot(p) - pl.offset));
  return d;
}

test::SyntheticScene wallsAndBall() {
  test::SyntheticScene s;
  s.planes.push_back({Eigen::Vector3d(0, 0, -1), -1.6});   // back wall z = 1.6
  s.planes.push_back({Eigen::Vector3d(0, -1, 0), -0.45});  // floor y = 0.45
  s.spheres.push_back({Eigen::Vector3d(0.1, 0.05, 1.1), 0.22});
  return s;
}

PipelineParams roomParams() {
  PipelineParams p;
  p.volume.voxel_size_m = 0.01f;
  return p;
}

// A hand-held sweep: 10 degrees of yaw, a little pitch and shake. Small enough that nearly every
// surface voxel is seen in many frames (a voxel seen once keeps a flipped label 20 % of the time).
Pose orbitPose(int i, int n) {
  const double a = -5.0 + 10.0 * i / std::max(1, n - 1);
  return test::poseFrom(1.5 * std::sin(i), a, 0, 0.02 * std::cos(0.7 * i), 0.01 * std::sin(1.3 * i), 0.0);
}

struct ClassScore {
  long long surface = 0, right = 0;
  double fraction() const { return surface ? double(right) / double(surface) : 0; }
};

// The bricks in coordinate order: the pool's order depends on which thread reached a brick first.
std::vector<size_t> bricksByCoordinate(const BrickVolumeView& v) {
  std::vector<size_t> order(v.brick_count);
  std::iota(order.begin(), order.end(), size_t(0));
  std::sort(order.begin(), order.end(), [&](size_t a, size_t b) {
    return std::tie(v.coords[a].x, v.coords[a].y, v.coords[a].z) < std::tie(v.coords[b].x, v.coords[b].y, v.coords[b].z);
  });
  return order;
}

// Calls f(index, centre) for every surface voxel: observed (weight > 0) and |sdf| < one voxel.
template <class F>
void forEachSurfaceVoxel(const BrickVolumeView& v, F f) {
  for (size_t n = 0; n < v.brick_count; ++n)
    for (int i = 0; i < kBrickVoxels; ++i) {
      const size_t index = n * kBrickVoxels + size_t(i);
      if (v.tsdf[index].weight == 0 || std::abs(v.sdfMetres(index)) >= v.voxel_size_m) continue;
      const Vec3i o = localVoxelOffset(i), b = v.coords[n];
      const Eigen::Vector3d centre((b.x * kBrickSize + o.x + 0.5) * v.voxel_size_m,
                                   (b.y * kBrickSize + o.y + 0.5) * v.voxel_size_m,
                                   (b.z * kBrickSize + o.z + 0.5) * v.voxel_size_m);
      f(index, centre);
    }
}

// Surface voxels whose class is that of the nearest primitive, within 0.96 m of the optical axis
// and 1.92 m of the camera: the part of the room every frame of the sweep sees (a voxel seen
// once keeps a flipped label 20 % of the time; the edges of the views are seen by few frames).
ClassScore scoreClasses(const BrickVolumeView& v, const test::SyntheticScene& s) {
  ClassScore score;
  forEachSurfaceVoxel(v, [&](size_t index, const Eigen::Vector3d& p) {
    if (std::abs(p.x()) > 0.96 || std::abs(p.y()) > 0.96 || p.z() > 1.92) return;
    const uint16_t truth = sphereDistance(s, p) < planeDistance(s, p) ? kBall : kStatic;
    const uint32_t vote = v.class_vote[index];
    ++score.surface;
    // The scene's class grid holds voteClass whatever the confidence; 0 = never voted.
    if (vote != 0 && voteClass(vote) == truth) ++score.right;
  });
  return score;
}

ClassScore fuseNoisyLabels(ClassVote mode, uint32_t seed, int frames, std::vector<uint32_t>* votes = nullptr,
                           Device device = Device::Cpu) {
  const test::SyntheticScene scene = wallsAndBall();
  const Intrinsics k = test::testCamera(160, 120);
  PipelineParams params = roomParams();
  params.integration.class_vote = mode;
  params.integration.class_vote_seed = seed;
  Pipeline pipeline(params, k, device, true);
  std::mt19937 rng(7);
  for (int i = 0; i < frames; ++i) {
    const Pose T = orbitPose(i, frames);
    RgbdFrame frame = scene.render(k, T);
    frame.labels = renderLabels(scene, k, T, 0.2, rng);
    frame.T_world_cam_given = T;
    frame.name = std::to_string(i);
    pipeline.processFrame(frame, PoseSource::Given);
  }
  const BrickVolumeView volume = pipeline.hostVolume();
  if (votes) {
    votes->clear();
    for (size_t brick : bricksByCoordinate(volume))
      for (int j = 0; j < kBrickVoxels; ++j) votes->push_back(volume.class_vote[brick * kBrickVoxels + size_t(j)]);
  }
  return scoreClasses(volume, scene);
}

TEST(SemanticFusion, MajorityVoteRecoversClassesUnderTwentyPercentLabelNoise) {
  const ClassScore score = fuseNoisyLabels(ClassVote::Majority, 0, 30);
  std::printf("majority: %lld surface voxels, %.3f%% right class\n", score.surface, 100 * score.fraction());
  ASSERT_GT(score.surface, 20000);
  EXPECT_GE(score.fraction(), 0.99);
}

TEST(SemanticFusion, ProbabilisticVoteIsReproducibleFromItsSeed) {
  std::vector<uint32_t> a, b, c;
  const ClassScore sa = fuseNoisyLabels(ClassVote::Probabilistic, 11, 30, &a);
  fuseNoisyLabels(ClassVote::Probabilistic, 11, 30, &b);
  fuseNoisyLabels(ClassVote::Probabilistic, 12, 30, &c);
  std::printf("probabilistic: %lld surface voxels, %.3f%% right class\n", sa.surface, 100 * sa.fraction());
  ASSERT_EQ(a.size(), b.size());
  EXPECT_TRUE(a == b) << "same seed, same frames: the votes must be identical";
  EXPECT_FALSE(a == c) << "another seed must draw other random numbers";
  // Under 20 % label noise the replacement rule is weaker than the majority vote, but still
  // classifies nearly all of the surface.
  EXPECT_GE(sa.fraction(), 0.90);
}

TEST(SemanticFusion, ProbabilisticVoteIsTheSameOnCpuAndCuda) {
  if (cudaDeviceCount() == 0) GTEST_SKIP() << "no usable CUDA device (or built without CUDA): parity not checked";
  std::vector<uint32_t> cpu, gpu;
  const ClassScore a = fuseNoisyLabels(ClassVote::Probabilistic, 5, 10, &cpu, Device::Cpu);
  const ClassScore b = fuseNoisyLabels(ClassVote::Probabilistic, 5, 10, &gpu, Device::Cuda);
  ASSERT_EQ(cpu.size(), gpu.size());
  size_t differ = 0;
  for (size_t i = 0; i < cpu.size(); ++i) differ += cpu[i] != gpu[i];
  std::printf("cpu %.3f%%, cuda %.3f%% right; %zu of %zu votes differ\n", 100 * a.fraction(), 100 * b.fraction(),
              differ, cpu.size());
  EXPECT_EQ(differ, 0u);
}

TEST(ClassVoteRule, ProbabilisticReplacesWithProbabilityOneOverConfidencePlusOne) {
  for (uint32_t conf : {1u, 3u, 9u}) {
    const uint32_t vote = packClassVote(5, conf);
    int replaced = 0;
    const int n = 200000;
    for (int voxel = 0; voxel < n; ++voxel) {
      const uint32_t out = voteUpdate(vote, 6, 255, true, 42, uint64_t(voxel), 17);
      if (out != vote) {
        ++replaced;
        ASSERT_EQ(out, packClassVote(6, 1));
      }
    }
    EXPECT_NEAR(double(replaced) / n, 1.0 / (conf + 1), 0.005) << "confidence " << conf;
  }
  // Agreeing labels and empty voxels behave as in the majority vote.
  EXPECT_EQ(voteUpdate(packClassVote(5, 3), 5, 255, true, 1, 2, 3), packClassVote(5, 4));
  EXPECT_EQ(voteUpdate(0, 7, 255, true, 1, 2, 3), packClassVote(7, 1));
  // Majority: a differing label lowers the confidence, at zero the next label takes the voxel.
  EXPECT_EQ(voteUpdate(packClassVote(5, 2), 6, 255), packClassVote(5, 1));
  EXPECT_EQ(voteUpdate(packClassVote(5, 1), 6, 255), packClassVote(5, 0));
  EXPECT_EQ(voteUpdate(packClassVote(5, 0), 6, 255), packClassVote(6, 1));
}

// A "person" ball crossing the room in front of static walls.
struct DynamicRun {
  long long static_surface = 0;  // surface voxels within 2 cm of a plane
  long long ball_surface = 0;    // surface voxels within 2 cm of any of the ball's positions
};

DynamicRun fuseMovingBall(bool with_ball, bool mask_dynamic) {
  const Intrinsics k = test::testCamera(160, 120);
  Pipeline pipeline(roomParams(), k, Device::Cpu, true);
  if (mask_dynamic) pipeline.setDynamicClasses({kBall});
  const int frames = 20;
  std::vector<test::Sphere> positions;
  std::mt19937 rng(3);
  for (int i = 0; i < frames; ++i) {
    test::SyntheticScene scene = wallsAndBall();
    scene.spheres.clear();
    if (with_ball) scene.spheres.push_back({Eigen::Vector3d(-0.35 + 0.7 * i / (frames - 1), 0.1, 1.05), 0.2});
    if (with_ball) positions.push_back(scene.spheres.back());
    const Pose T = orbitPose(i, frames);
    RgbdFrame frame = scene.render(k, T);
    frame.labels = renderLabels(scene, k, T, 0.0, rng);
    frame.T_world_cam_given = T;
    pipeline.processFrame(frame, PoseSource::Given);
  }
  test::SyntheticScene all = wallsAndBall();
  all.spheres = positions;
  DynamicRun run;
  forEachSurfaceVoxel(pipeline.hostVolume(), [&](size_t, const Eigen::Vector3d& p) {
    if (planeDistance(all, p) < 0.02) ++run.static_surface;
    else if (!positions.empty() && sphereDistance(all, p) < 0.02) ++run.ball_surface;
  });
  return run;
}

TEST(SemanticFusion, DynamicClassLeavesNoGeometryAndKeepsTheStaticScene) {
  const DynamicRun empty_room = fuseMovingBall(false, false);
  const DynamicRun plain = fuseMovingBall(true, false);
  const DynamicRun masked = fuseMovingBall(true, true);
  std::printf("static surface voxels: empty room %lld, ball fused %lld, ball masked %lld\n",
              empty_room.static_surface, plain.static_surface, masked.static_surface);
  std::printf("ball surface voxels: fused %lld, masked %lld\n", plain.ball_surface, masked.ball_surface);
  ASSERT_GT(plain.ball_surface, 2000) << "without the option the moving ball leaves surfaces";
  EXPECT_LE(masked.ball_surface, plain.ball_surface / 100) << "dynamic class must leave (almost) no geometry";
  EXPECT_GE(double(masked.static_surface), 0.97 * double(empty_room.static_surface));
  EXPECT_LE(double(masked.static_surface), 1.01 * double(empty_room.static_surface));
}

}  // namespace
}  // namespace vf
