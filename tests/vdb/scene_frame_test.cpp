// Which way is up (vdb/scene_frame.h): the estimate on synthetic rooms and on the shared
// captures against independent gravity (TUM's motion-capture z, the phone's ARKit +y), the
// export rotations, and the metadata that records them.
#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <vector>

#include "core/error.h"
#include "fusion/pipeline.h"
#include "io/record3d.h"
#include "io/tum_dataset.h"
#include "synthetic_scene.h"
#include "test_data.h"
#include "vdb/brick_surface.h"
#include "vdb/scene.h"
#include "vdb/scene_export.h"
#include "vdb/scene_frame.h"

namespace vf {
namespace {

double angleDeg(Vec3f a, Vec3f b) {
  return std::acos(std::clamp(double(dot(normalized(a), normalized(b))), -1.0, 1.0)) * 180.0 / M_PI;
}

Vec3f toVec(const Eigen::Vector3d& v) { return {float(v.x()), float(v.y()), float(v.z())}; }

// Cameras 1.2 m above a floor at y = +0.3 (camera frame: y down), looking down by `pitch_deg`,
// panning a little, towards a wall that holds more surface than the floor.
Trajectory pitchedCameras(double pitch_deg) {
  Trajectory t;
  for (int i = 0; i < 10; ++i) {
    StampedPose p;
    p.T_world_cam.linear() = (Eigen::AngleAxisd((i - 4.5) * 0.03, Eigen::Vector3d::UnitY()) *
                              Eigen::AngleAxisd(-pitch_deg * M_PI / 180.0, Eigen::Vector3d::UnitX()))
                                 .toRotationMatrix();
    p.T_world_cam.translation() = Eigen::Vector3d(0.02 * i, -0.9, -0.6);
    t.push_back(p);
  }
  return t;
}

Scene roomScene(float floor_y, float wall_z) {
  test::SyntheticVolume volume(test::sphereSpec(96, 0.02f), false);
  test::fillSdf(volume, [&](Vec3f p) { return std::min(floor_y - p.y, wall_z - p.z); }, 0.f);
  return sceneFromBricks(volume.view(), {});
}

TEST(SceneUp, FloorPlaneBelowPitchedCamerasGivesUp) {
  // The cameras' up leans forward by the pitch: the floor's normal is `pitch` from it, the wall's
  // 90 + pitch.
  Scene scene = roomScene(0.3f, 0.1f);
  for (const double pitch : {10.0, 30.0, 40.0}) {
    const Trajectory cams = pitchedCameras(pitch);
    const SceneUp up = setSceneFrame(scene, cams);
    EXPECT_EQ(up.source, kUpFromFloorPlane) << pitch << ": " << up.detail;
    EXPECT_LT(angleDeg(up.up, {0, -1, 0}), 1.0) << pitch;
    EXPECT_NEAR(dot(up.up, up.forward), 0.f, 1e-5f);
    // Forward: the first camera's view, made horizontal (+z here).
    EXPECT_LT(angleDeg(up.forward, {std::sin(float(-4.5 * 0.03)), 0, std::cos(float(-4.5 * 0.03))}), 1.0);
    EXPECT_EQ(scene.meta.up_source, kUpFromFloorPlane);
  }
}

bool lessPoint(const Vec3f& a, const Vec3f& b) {
  return a.x != b.x ? a.x < b.x : a.y != b.y ? a.y < b.y : a.z < b.z;
}

TEST(SurfaceSamples, FromBricksAreTheScenePointCloudsPointsAndAQuarterOfThemOnRequest) {
  test::SyntheticVolume volume(test::sphereSpec(96, 0.02f), false);
  test::fillSdf(volume, [&](Vec3f p) { return std::min(0.3f - p.y, norm(p - Vec3f{0.2f, 0.f, 0.1f}) - 0.4f); }, 0.f);
  const TriangleMesh grid = scenePointCloud(sceneFromBricks(volume.view(), {}));
  const TriangleMesh bricks = brickSurfaceSamples(volume.view());
  ASSERT_GT(grid.positions.size(), 5000u);
  ASSERT_EQ(bricks.positions.size(), grid.positions.size());
  ASSERT_EQ(bricks.normals.size(), bricks.positions.size());
  // Same points (each with its normal), in another order.
  auto sorted = [](const TriangleMesh& m) {
    std::vector<std::pair<Vec3f, Vec3f>> p;
    for (size_t i = 0; i < m.positions.size(); ++i) p.push_back({m.positions[i], m.normals[i]});
    std::sort(p.begin(), p.end(), [](const auto& a, const auto& b) { return lessPoint(a.first, b.first); });
    return p;
  };
  const auto a = sorted(grid), b = sorted(bricks);
  size_t differing = 0;
  for (size_t i = 0; i < a.size(); ++i)
    differing += lessPoint(a[i].first, b[i].first) || lessPoint(b[i].first, a[i].first) ||
                 norm(a[i].second - b[i].second) > 1e-6f;
  EXPECT_EQ(differing, 0u);
  const size_t quarter = brickSurfaceSamples(volume.view(), 4).positions.size();
  EXPECT_NEAR(double(quarter), a.size() / 4.0, a.size() * 0.02);
}

TEST(SurfaceSamples, DoNotDependOnWhichPoolSlotEachBrickGot) {
  // Integration hands out slots in whatever order its threads reach the bricks; the samples
  // (and the floor plane fitted to them) must come out the same, in the same order.
  test::SyntheticVolume volume(test::sphereSpec(64, 0.02f), false);
  test::fillSdf(volume, [&](Vec3f p) { return std::min(0.3f - p.y, norm(p - Vec3f{0.1f, 0.f, 0.f}) - 0.3f); }, 0.f);
  const BrickVolumeView v = volume.view();
  ASSERT_GT(v.brick_count, 100u);
  std::vector<size_t> slot_of(v.brick_count);  // a fixed shuffle: reversed, odd slots first
  size_t next = 0;
  for (int odd = 1; odd >= 0; --odd)
    for (size_t n = v.brick_count; n-- > 0;)
      if (int(n % 2) == odd) slot_of[n] = next++;
  std::vector<Vec3i> coords(v.brick_count);
  std::vector<TsdfVoxel> tsdf(v.brick_count * kBrickVoxels);
  for (size_t n = 0; n < v.brick_count; ++n) {
    coords[slot_of[n]] = v.coords[n];
    std::copy(v.tsdf + n * kBrickVoxels, v.tsdf + (n + 1) * kBrickVoxels, tsdf.begin() + slot_of[n] * kBrickVoxels);
  }
  BrickVolumeView shuffled = v;
  shuffled.coords = coords.data();
  shuffled.tsdf = tsdf.data();
  shuffled.color = nullptr;
  const TriangleMesh a = brickSurfaceSamples(v, 4), b = brickSurfaceSamples(shuffled, 4);
  ASSERT_GT(a.positions.size(), 1000u);
  ASSERT_EQ(a.positions.size(), b.positions.size());
  size_t differing = 0;
  for (size_t i = 0; i < a.positions.size(); ++i)
    differing += lessPoint(a.positions[i], b.positions[i]) || lessPoint(b.positions[i], a.positions[i]);
  EXPECT_EQ(differing, 0u);
}

TEST(SceneUp, WithoutAFloorTheCamerasMeanUpIsUsed) {
  test::SyntheticVolume volume(test::sphereSpec(64, 0.01f), false);
  test::fillSdf(volume, test::sphereSdf({0, 0, 0}, 0.2f), 0.f);
  Scene ball = sceneFromBricks(volume.view(), {});
  const Trajectory cams = pitchedCameras(20.0);
  const SceneUp up = setSceneFrame(ball, cams);
  EXPECT_EQ(up.source, kUpFromCameraUp) << up.detail;
  Eigen::Vector3d mean = Eigen::Vector3d::Zero();
  for (const StampedPose& p : cams) mean -= p.T_world_cam.linear().col(1);
  EXPECT_LT(angleDeg(up.up, toVec(mean)), 0.01);
  // No trajectory at all: the first camera's -y.
  EXPECT_LT(angleDeg(setSceneFrame(ball, {}).up, {0, -1, 0}), 0.01);
}

TEST(SceneUp, RecordedUpIsCarriedIntoTheFusedFrame) {
  // The device recorded camera 0 at R (its world: +y up); fusion put camera 0 at the identity.
  Pose T_recorded = Pose::Identity();
  T_recorded.linear() = Eigen::AngleAxisd(0.4, Eigen::Vector3d(1, 2, 3).normalized()).toRotationMatrix();
  T_recorded.translation() = Eigen::Vector3d(1, 2, 3);
  const Vec3f up = recordedUpInFusedFrame({0, 1, 0}, T_recorded, Pose::Identity());
  EXPECT_LT(angleDeg(up, toVec(T_recorded.linear().transpose() * Eigen::Vector3d::UnitY())), 1e-3);
  // Fusion keeping the recorded frame: up stays +y.
  EXPECT_LT(angleDeg(recordedUpInFusedFrame({0, 1, 0}, T_recorded, T_recorded), {0, 1, 0}), 1e-3);
  const SceneUp est = estimateSceneUp(pitchedCameras(30), TriangleMesh{}, up);
  EXPECT_EQ(est.source, kUpFromRecordedPoses);
  EXPECT_LT(angleDeg(est.up, up), 1e-3);
}

TEST(SceneAxes, RotationsPutUpWhereEachFormatWantsIt) {
  SceneMetadata meta;
  meta.up_world = normalized(Vec3f{0.1f, -1.f, 0.2f});
  meta.forward_world = normalized(Vec3f{0, 0, 1} - meta.up_world * dot(Vec3f{0, 0, 1}, meta.up_world));
  const Rigid3f z = exportRotation(meta, SceneAxes::kZUp), y = exportRotation(meta, SceneAxes::kYUp);
  EXPECT_LT(angleDeg(z.rotate(meta.up_world), {0, 0, 1}), 1e-3);
  EXPECT_LT(angleDeg(z.rotate(meta.forward_world), {0, 1, 0}), 1e-3);
  EXPECT_LT(angleDeg(y.rotate(meta.up_world), {0, 1, 0}), 1e-3);
  EXPECT_LT(angleDeg(y.rotate(meta.forward_world), {0, 0, -1}), 1e-3);
  // Proper rotations (no mirror): x = forward x up stays the camera's right.
  for (const Rigid3f& r : {z, y}) {
    const Vec3f c0{r.r[0], r.r[3], r.r[6]}, c1{r.r[1], r.r[4], r.r[7]}, c2{r.r[2], r.r[5], r.r[8]};
    EXPECT_NEAR(dot(cross(c0, c1), c2), 1.f, 1e-5f);
  }
  // camera: as fused; no metadata: the first camera upright (-y up, +z forward).
  const Rigid3f cam = exportRotation(meta, SceneAxes::kCamera);
  EXPECT_EQ(cam.rotate({1, 2, 3}).y, 2.f);
  EXPECT_LT(angleDeg(exportRotation(SceneMetadata{}, SceneAxes::kZUp).rotate({0, -1, 0}), {0, 0, 1}), 1e-3);
  EXPECT_THROW(parseSceneAxes("x-up"), Error);
  EXPECT_EQ(parseSceneAxes("y-up"), SceneAxes::kYUp);
}

TEST(SceneMetadataIo, UpAndCameraRoundTripAndBadValuesAreRefused) {
  Scene scene = roomScene(0.3f, 0.1f);
  setSceneFrame(scene, pitchedCameras(20));
  scene.meta.depth_intrinsics = {191.2f, 191.3f, 95.8f, 129.4f, 192, 256};
  const std::string dir = test::tempDir("scene_frame_meta");
  writeScene(scene, dir + "/scene.vdb");
  const Scene back = readScene(dir + "/scene.vdb");
  EXPECT_EQ(back.meta.up_source, kUpFromFloorPlane);
  EXPECT_LT(angleDeg(back.meta.up_world, scene.meta.up_world), 1e-4);
  EXPECT_LT(angleDeg(back.meta.forward_world, scene.meta.forward_world), 1e-4);
  EXPECT_EQ(back.meta.depth_intrinsics.fy, 191.3f);
  EXPECT_EQ(back.meta.depth_intrinsics.height, 256);
  // A scene written without them reads with none.
  Scene plain = roomScene(0.3f, 0.1f);
  writeScene(plain, dir + "/plain.vdb");
  EXPECT_EQ(norm(readScene(dir + "/plain.vdb").meta.up_world), 0.f);
  EXPECT_FALSE(readScene(dir + "/plain.vdb").meta.depth_intrinsics.valid());
  // Not a unit vector: the file is refused, naming the key.
  scene.meta.up_world = {0, -2, 0};
  writeScene(scene, dir + "/bad.vdb");
  const std::string error = test::errorOf([&] { readScene(dir + "/bad.vdb"); });
  EXPECT_NE(error.find("vdbfuse_up"), std::string::npos) << error;
}

// ---- real captures: the estimate against gravity measured by other means ----

struct Fused {
  Scene scene;
  Trajectory trajectory;
  HostBrickVolume bricks;  // a copy of the pipeline's
};

Fused fuse(const FrameSource& source, int frames, PoseSource poses) {
  PipelineParams params;
  params.volume.voxel_size_m = 0.02f;
  Pipeline pipeline(params, source.depthIntrinsics(), Device::Cpu, false);
  Fused out;
  for (int i = 0; i < frames; ++i) {
    const RgbdFrame frame = source.load(i);
    out.trajectory.push_back({frame.timestamp, pipeline.processFrame(frame, poses).T_world_cam});
  }
  out.bricks = HostBrickVolume::copyOf(pipeline.hostVolume());
  out.scene = sceneFromBricks(out.bricks.view(), {});
  return out;
}

TEST(SceneUpOnRealData, TumIcpSceneFindsTheMotionCaptureUp) {
  // TUM's motion-capture world is z-up (the cameras' image -y points along +z in groundtruth.txt);
  // a frame with a motion-capture pose carries that z into fusion's frame. (fr1/xyz, whose
  // cameras look 42 degrees down, is checked the same way by vdb_blender_test's TumInBlender.)
  for (const char* name : {"tum_fr3_teddy_head60"}) {
    VF_REQUIRE_DATA(folder, name);
    const TumDataset tum(folder);
    Fused f = fuse(tum, 20, PoseSource::Icp);
    int with_gt = 0;
    while (with_gt < 20 && !tum.load(with_gt).T_world_cam_given) ++with_gt;
    ASSERT_LT(with_gt, 20) << name << ": no frame with a motion-capture pose";
    const Vec3f truth = recordedUpInFusedFrame({0, 0, 1}, *tum.load(with_gt).T_world_cam_given,
                                               f.trajectory[size_t(with_gt)].T_world_cam);
    const SceneUp up = setSceneFrame(f.scene, f.trajectory);
    std::printf("%s: up from %s (%s), %.1f degrees from the motion capture's\n", name, up.source.c_str(),
                up.detail.c_str(), angleDeg(up.up, truth));
    EXPECT_EQ(up.source, kUpFromFloorPlane) << name;
    EXPECT_LT(angleDeg(up.up, truth), 10.0) << name;
    // reconstruct's way, from a quarter of the bricks' surface samples: the same floor.
    SceneMetadata meta;
    const SceneUp from_bricks = setSceneFrame(meta, f.bricks.view(), f.trajectory, tum);
    EXPECT_EQ(from_bricks.source, kUpFromFloorPlane) << from_bricks.detail;
    EXPECT_LT(angleDeg(from_bricks.up, up.up), 1.0);
    EXPECT_EQ(meta.up_source, kUpFromFloorPlane);
    EXPECT_TRUE(meta.depth_intrinsics.valid());
  }
}

TEST(SceneUpOnRealData, DanceFloorPlaneAgreesWithTheRecordedArkitUp) {
  VF_REQUIRE_DATA(capture, "record3d_dance_head200.r3d");
  const Record3dCapture r3d(capture);
  ASSERT_TRUE(r3d.worldUp().has_value()) << "the capture's metadata has initPose";
  Fused f = fuse(r3d, 40, PoseSource::Given);
  const SceneUp recorded = setSceneFrame(f.scene, f.trajectory, r3d);
  EXPECT_EQ(recorded.source, kUpFromRecordedPoses);
  const SceneUp estimated = estimateSceneUp(f.trajectory, scenePointCloud(f.scene));
  std::printf("dance: recorded up vs %s (%s): %.1f degrees\n", estimated.source.c_str(), estimated.detail.c_str(),
              angleDeg(recorded.up, estimated.up));
  EXPECT_LT(angleDeg(recorded.up, estimated.up), 10.0);
}

}  // namespace
}  // namespace vf
