// Point-to-surface distances (TriangleBvh), surface sampling, visibility and the accuracy /
// completion / F-score figures on meshes whose answers are known.
#include <gtest/gtest.h>

#include <cmath>
#include <random>

#include "core/error.h"
#include "io/mesh_metrics.h"
#include "io/trajectory_alignment.h"
#include "io/triangle_bvh.h"
#include "test_data.h"

namespace vf {
namespace {

using test::errorOf;

// A size x size square in the plane z = z0, as a grid of n x n cells (2 triangles each).
TriangleMesh squareMesh(float size, float z0, int n = 4) {
  TriangleMesh m;
  for (int y = 0; y <= n; ++y)
    for (int x = 0; x <= n; ++x) m.positions.push_back({size * x / n - size / 2, size * y / n - size / 2, z0});
  for (int y = 0; y < n; ++y)
    for (int x = 0; x < n; ++x) {
      const int a = y * (n + 1) + x;
      m.triangles.push_back({a, a + 1, a + n + 2});
      m.triangles.push_back({a, a + n + 2, a + n + 1});
    }
  return m;
}

// Sphere of radius r: a latitude/longitude grid fine enough that its chords stay within 0.05 mm.
TriangleMesh sphereMesh(float r, Vec3f centre = {0, 0, 0}, int rings = 200, int segments = 400) {
  TriangleMesh m;
  for (int i = 0; i <= rings; ++i)
    for (int j = 0; j < segments; ++j) {
      const double th = M_PI * i / rings, ph = 2 * M_PI * j / segments;
      m.positions.push_back(centre + Vec3f{float(r * std::sin(th) * std::cos(ph)), float(r * std::sin(th) * std::sin(ph)),
                                           float(r * std::cos(th))});
    }
  for (int i = 0; i < rings; ++i)
    for (int j = 0; j < segments; ++j) {
      const int a = i * segments + j, b = i * segments + (j + 1) % segments;
      m.triangles.push_back({a, a + segments, b});
      m.triangles.push_back({b, a + segments, b + segments});
    }
  return m;
}

float bruteForceDistance(const TriangleMesh& m, Vec3f p) {
  float best = INFINITY;
  for (const auto& t : m.triangles) {
    const Vec3f a = m.positions[size_t(t[0])], b = m.positions[size_t(t[1])], c = m.positions[size_t(t[2])];
    if (!(norm(cross(b - a, c - a)) > 0)) continue;
    best = std::min(best, norm(p - closestPointOnTriangle(p, a, b, c)));
  }
  return best;
}

TEST(TriangleBvh, ClosestPointCoversFaceEdgeAndVertexRegions) {
  const Vec3f a{0, 0, 0}, b{1, 0, 0}, c{0, 1, 0};
  const Vec3f face = closestPointOnTriangle({0.2f, 0.2f, 3}, a, b, c);
  EXPECT_NEAR(face.x, 0.2f, 1e-6);
  EXPECT_NEAR(face.z, 0.f, 1e-6);
  const Vec3f edge = closestPointOnTriangle({0.5f, -1, 0}, a, b, c);
  EXPECT_NEAR(edge.x, 0.5f, 1e-6);
  EXPECT_NEAR(edge.y, 0.f, 1e-6);
  const Vec3f hyp = closestPointOnTriangle({1, 1, 0}, a, b, c);
  EXPECT_NEAR(hyp.x, 0.5f, 1e-6);
  EXPECT_NEAR(hyp.y, 0.5f, 1e-6);
  const Vec3f vertex = closestPointOnTriangle({-1, -2, 0.5f}, a, b, c);
  EXPECT_EQ(vertex.x, 0.f);
  EXPECT_EQ(vertex.y, 0.f);
}

TEST(TriangleBvh, MatchesBruteForceOnRandomTrianglesAndPoints) {
  std::mt19937 rng(7);
  std::uniform_real_distribution<float> u(-1, 1);
  TriangleMesh m;
  for (int i = 0; i < 600; ++i) {
    const Vec3f c{u(rng), u(rng), u(rng)};
    for (int k = 0; k < 3; ++k) m.positions.push_back(c + Vec3f{0.2f * u(rng), 0.2f * u(rng), 0.2f * u(rng)});
    m.triangles.push_back({3 * i, 3 * i + 1, 3 * i + 2});
  }
  m.positions.push_back({5, 5, 5});  // a zero-area triangle: no surface, must be ignored
  m.triangles.push_back({int(m.positions.size()) - 1, int(m.positions.size()) - 1, int(m.positions.size()) - 1});
  const TriangleBvh bvh(m);
  EXPECT_EQ(bvh.triangleCount(), 600u);
  std::vector<Vec3f> points;
  for (int i = 0; i < 500; ++i) points.push_back({2 * u(rng), 2 * u(rng), 2 * u(rng)});
  const std::vector<float> d = bvh.distances(points);
  for (size_t i = 0; i < points.size(); ++i) ASSERT_NEAR(d[i], bruteForceDistance(m, points[i]), 1e-5) << i;
  EXPECT_TRUE(std::isinf(bvh.distance({30, 0, 0}, 1.f))) << "nothing within max_distance";
}

TEST(TriangleBvh, DistanceIsToTheSurfaceNotToVertices) {
  const TriangleBvh bvh(squareMesh(2.f, 0.f, 1));  // two triangles, vertices 1.41 m from the centre
  EXPECT_NEAR(bvh.distance({0.1f, -0.2f, 0.03f}), 0.03f, 1e-6);
}

TEST(TriangleBvh, MeshWithoutAreaOrWithBadIndicesIsAnError) {
  TriangleMesh m;
  m.positions = {{0, 0, 0}, {1, 0, 0}};
  m.triangles = {{0, 1, 1}};
  EXPECT_NE(errorOf([&] { TriangleBvh b(m); }).find("no triangle with an area"), std::string::npos);
  m.triangles = {{0, 1, 7}};
  EXPECT_NE(errorOf([&] { TriangleBvh b(m); }).find("vertex 7"), std::string::npos);
}

// Issue 35: one triangle given 5,000 times (in any corner order) is one surface. The copies shared
// one leaf that no split could divide, and every query tested all of them: evaluate --mesh ran
// for over a minute.
TEST(TriangleBvh, ATriangleGivenManyTimesIsKeptOnce) {
  TriangleMesh m;
  m.positions = {{0, 0, 0}, {1, 0, 0}, {0, 1, 0}, {0, 0, 0}, {1, 0, 0}, {0, 1, 0}};
  for (int i = 0; i < 5000; ++i) {
    const int base = 3 * (i % 2);  // the same corners through other vertices too
    m.triangles.push_back({base + i % 3, base + (i + 1) % 3, base + (i + 2) % 3});
  }
  m.triangles.push_back({0, 2, 1});  // reversed winding: the same surface
  const TriangleBvh bvh(m);
  EXPECT_EQ(bvh.triangleCount(), 1u);
  EXPECT_NEAR(bvh.distance({0.2f, 0.2f, 0.5f}), 0.5f, 1e-6);
  EXPECT_NEAR(bvh.distance({2, 0, 0}), 1.f, 1e-6);
}

// Distinct triangles about one centroid (a fan of rotated copies): the centroid split has nothing
// to split on, so the build splits by count; distances stay exact.
TEST(TriangleBvh, TrianglesSharingACentroidAreStillSearchedExactly) {
  TriangleMesh m;
  for (int i = 0; i < 2000; ++i) {
    const float a = 2.f * float(M_PI) * float(i) / 2000.f;
    const Vec3f u{std::cos(a), std::sin(a), 0.f}, v{-std::sin(a), std::cos(a), 0.3f};
    const int base = int(m.positions.size());
    m.positions.push_back(u);
    m.positions.push_back(v);
    m.positions.push_back(Vec3f{0, 0, 0} - u - v);  // the centroid is the origin for every one
    m.triangles.push_back({base, base + 1, base + 2});
  }
  const TriangleBvh bvh(m);
  EXPECT_EQ(bvh.triangleCount(), 2000u);
  std::mt19937 rng(5);
  std::uniform_real_distribution<float> u(-2, 2);
  std::vector<Vec3f> points;
  for (int i = 0; i < 200; ++i) points.push_back({u(rng), u(rng), u(rng)});
  const std::vector<float> d = bvh.distances(points);
  for (size_t i = 0; i < points.size(); ++i) ASSERT_NEAR(d[i], bruteForceDistance(m, points[i]), 1e-5) << i;
}

TEST(SurfaceSampling, IsAreaWeightedUniformAndDeterministic) {
  TriangleMesh two = squareMesh(1.f, 0.f, 1);  // 1 m^2 at z = 0
  const TriangleMesh big = squareMesh(2.f, 1.f, 1);  // 4 m^2 at z = 1
  for (const Vec3f& p : big.positions) two.positions.push_back(p);
  for (const auto& t : big.triangles) two.triangles.push_back({t[0] + 4, t[1] + 4, t[2] + 4});
  EXPECT_NEAR(surfaceArea(two), 5.0, 1e-6);
  const std::vector<Vec3f> s = sampleSurface(two, 100000, 3);
  int on_big = 0, left = 0;
  for (const Vec3f& p : s) {
    on_big += p.z > 0.5f;
    if (p.z > 0.5f) left += p.x < 0;
  }
  EXPECT_NEAR(on_big / 100000.0, 0.8, 0.005);
  EXPECT_NEAR(double(left) / on_big, 0.5, 0.01);  // uniform within the square
  const std::vector<Vec3f> again = sampleSurface(two, 100000, 3);
  EXPECT_EQ(again[12345].x, s[12345].x);
  EXPECT_NE(sampleSurface(two, 10, 4)[0].x, s[0].x);
}

TEST(SurfaceMetrics, MeshAgainstItselfShiftedByOneCentimetre) {
  const TriangleMesh reference = sphereMesh(1.f);
  const TriangleMesh shifted = sphereMesh(1.01f);  // every point 1 cm off the reference surface
  const TriangleBvh ref(reference), rec(shifted);
  const std::vector<Vec3f> rec_points = sampleSurface(shifted, 200000, 1), ref_points = sampleSurface(reference, 200000, 2);
  const SurfaceMetrics at5 = surfaceMetrics(ref.distances(rec_points), rec.distances(ref_points), 0.05);
  EXPECT_NEAR(at5.accuracy_median_m, 0.01, 1e-4);
  EXPECT_NEAR(at5.accuracy_mean_m, 0.01, 1e-4);
  EXPECT_NEAR(at5.completion_median_m, 0.01, 1e-4);
  EXPECT_DOUBLE_EQ(at5.completion_ratio, 1.0);
  EXPECT_DOUBLE_EQ(at5.fscore, 1.0);
  const SurfaceMetrics at5mm = surfaceMetrics(ref.distances(rec_points), rec.distances(ref_points), 0.005);
  EXPECT_DOUBLE_EQ(at5mm.completion_ratio, 0.0);
  EXPECT_DOUBLE_EQ(at5mm.fscore, 0.0);
}

TEST(SurfaceMetrics, HalfAReferenceMissingHalvesCompletionNotAccuracy) {
  // The reconstruction covers the left half of the reference square, 2 mm above it.
  const TriangleMesh reference = squareMesh(2.f, 0.f, 8);
  TriangleMesh half = squareMesh(1.f, 0.002f, 4);
  for (Vec3f& p : half.positions) p.x = p.x * 1.f - 0.5f, p.y *= 2.f;  // x in [-1, 0], y in [-1, 1]
  const TriangleBvh ref(reference), rec(half);
  const std::vector<Vec3f> rec_points = sampleSurface(half, 100000, 1), ref_points = sampleSurface(reference, 100000, 2);
  const SurfaceMetrics m = surfaceMetrics(ref.distances(rec_points), rec.distances(ref_points), 0.05);
  EXPECT_NEAR(m.accuracy_median_m, 0.002, 1e-5);
  EXPECT_DOUBLE_EQ(m.precision, 1.0);
  EXPECT_NEAR(m.completion_ratio, 0.5 + 0.05 / 2, 0.01);  // the right half within 5 cm of the edge counts
  EXPECT_NEAR(m.fscore, 2 * 0.525 / 1.525, 0.01);
}

TEST(MarkSeen, CountsOnlyPointsInTheFrustumDepthRangeAndNotHidden) {
  Intrinsics k{50, 50, 50, 50, 100, 100};  // 90 degrees wide
  const std::vector<Vec3f> points = {{0, 0, 1}, {0.8f, 0, 1}, {1.5f, 0, 1}, {0, 0, 5}, {0, 0, -1}, {0, 0, 0.1f}};
  ViewCamera camera;
  camera.intrinsics = k;
  std::vector<uint8_t> seen(points.size(), 0);
  markSeen(points, camera, seen);
  EXPECT_EQ(seen, (std::vector<uint8_t>{1, 1, 0, 0, 0, 0}));  // outside, too far, behind, too near
  // A wall at 0.5 m in the depth map hides the point at 1 m; a hole (0) is not seen either.
  DepthImage depth(100, 100, 0.5f);
  depth(90, 50) = 0.f;  // where {0.8, 0, 1} projects
  camera.depth = &depth;
  std::vector<uint8_t> hidden(points.size(), 0);
  markSeen(points, camera, hidden);
  EXPECT_EQ(hidden[0], 0);
  EXPECT_EQ(hidden[1], 0);
  camera.T_world_cam.translation() = Eigen::Vector3d(0, 0, 0.5);  // now 0.5 m from the point: at the wall
  markSeen(points, camera, hidden);
  EXPECT_EQ(hidden[0], 1);
}

Trajectory movedTrajectory(const Trajectory& t, const Pose& T) {
  Trajectory out = t;
  for (StampedPose& p : out) p.T_world_cam = T * p.T_world_cam;
  return out;
}

TEST(TrajectoryAlignment, AteAndFirstPoseRecoverAKnownMotion) {
  Trajectory gt;
  for (int i = 0; i < 20; ++i) {
    StampedPose p;
    p.timestamp = i / 30.0;
    p.T_world_cam.translation() = Eigen::Vector3d(0.1 * std::cos(i * 0.3), 0.05 * i, 0.1 * std::sin(i * 0.3));
    p.T_world_cam.linear() = Eigen::AngleAxisd(0.05 * i, Eigen::Vector3d::UnitY()).toRotationMatrix();
    gt.push_back(p);
  }
  Pose T_gt_est = Pose::Identity();
  T_gt_est.linear() = Eigen::AngleAxisd(0.7, Eigen::Vector3d(1, 2, 3).normalized()).toRotationMatrix();
  T_gt_est.translation() = Eigen::Vector3d(1, -2, 0.5);
  const Trajectory est = movedTrajectory(gt, T_gt_est.inverse());
  for (const AlignmentMethod m : {AlignmentMethod::Auto, AlignmentMethod::Ate, AlignmentMethod::FirstPose}) {
    const TrajectoryAlignment a = alignTrajectory(est, gt, m);
    EXPECT_LT((a.T_gt_est.matrix() - T_gt_est.matrix()).cwiseAbs().maxCoeff(), 1e-9) << a.description;
  }
  EXPECT_EQ(alignTrajectory(est, gt, AlignmentMethod::Auto).method, AlignmentMethod::Ate);
  EXPECT_TRUE(alignTrajectory(est, gt, AlignmentMethod::None).T_gt_est.isApprox(Pose::Identity()));
}

TEST(TrajectoryAlignment, AutoUsesTheFirstPoseWhenTheCameraMovesAlongALine) {
  Trajectory gt;
  for (int i = 0; i < 4; ++i) {
    StampedPose p;
    p.timestamp = i;
    p.T_world_cam.translation() = Eigen::Vector3d(0.01 * i, 0, 0);
    gt.push_back(p);
  }
  Pose T = Pose::Identity();
  T.linear() = Eigen::AngleAxisd(0.5, Eigen::Vector3d::UnitX()).toRotationMatrix();  // about the line
  const TrajectoryAlignment a = alignTrajectory(movedTrajectory(gt, T.inverse()), gt, AlignmentMethod::Auto);
  EXPECT_EQ(a.method, AlignmentMethod::FirstPose);
  EXPECT_NE(a.description.find("line"), std::string::npos);
  EXPECT_LT((a.T_gt_est.matrix() - T.matrix()).cwiseAbs().maxCoeff(), 1e-9);
}

}  // namespace
}  // namespace vf
