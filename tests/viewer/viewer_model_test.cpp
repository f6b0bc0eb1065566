// The viewer's plain side: option values, what is read from a scene (class rows, per-class
// parts, bounds, trajectory), slices through the grids, merged exports. No display needed.
#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <fstream>

#include "core/error.h"
#include "test_data.h"
#include "vdb/mesher.h"
#include "vdb/scene_info.h"
#include "viewer/frustum_poses.h"
#include "viewer/level_frame.h"
#include "viewer/scene_content.h"
#include "viewer/slice.h"
#include "viewer/view_options.h"
#include "viewer/view_style.h"
#include "viewer_scenes.h"

namespace vf::viewer {
namespace {

TEST(ViewOptions, ParsesSliceCameraAndSize) {
  const SliceSpec s = parseSliceSpec("y:-0.25");
  EXPECT_TRUE(s.enabled);
  EXPECT_EQ(s.axis, 1);
  EXPECT_FLOAT_EQ(s.value_m, -0.25f);
  EXPECT_EQ(parseSliceSpec("x:1").axis, 0);
  for (const char* bad : {"w:1", "z:", "z", "z:abc", "z=1", "z:1.5m", "height=", "height=1m", "height"})
    EXPECT_THROW(parseSliceSpec(bad), Error) << bad;
  for (const char* floor_plan : {"height=1.25", "height:1.25"}) {
    const SliceSpec h = parseSliceSpec(floor_plan);
    EXPECT_TRUE(h.enabled && h.level) << floor_plan;
    EXPECT_FLOAT_EQ(h.value_m, 1.25f);
  }
  const std::string error = test::errorOf([] { parseSliceSpec("floor"); });
  EXPECT_NE(error.find("height=METRES"), std::string::npos) << error;

  EXPECT_EQ(parseCameraSpec("front").preset, CameraPreset::kFront);
  EXPECT_EQ(parseCameraSpec("top").preset, CameraPreset::kTop);
  EXPECT_EQ(parseCameraSpec("side").preset, CameraPreset::kSide);
  const CameraSpec c = parseCameraSpec("trajectory:12");
  EXPECT_EQ(c.preset, CameraPreset::kTrajectory);
  EXPECT_EQ(c.frame, 12);
  for (const char* bad : {"back", "trajectory:", "trajectory:-1", "trajectory:1x"})
    EXPECT_THROW(parseCameraSpec(bad), Error) << bad;

  int w = 0, h = 0;
  parseWindowSize("1280x720", w, h);
  EXPECT_EQ(w, 1280);
  EXPECT_EQ(h, 720);
  for (const char* bad : {"1280", "0x10", "1280x", "x720", "99999x10"}) EXPECT_THROW(parseWindowSize(bad, w, h), Error);
  try {
    parseWindowSize("1280", w, h);
  } catch (const Error& e) {
    EXPECT_NE(std::string(e.what()).find("WIDTHxHEIGHT"), std::string::npos) << e.what();
  }
}

TEST(ViewOptions, ScreenshotFormatByExtension) {
  EXPECT_EQ(pictureFormatFromPath("a/b.png"), PictureFormat::kPng);
  EXPECT_EQ(pictureFormatFromPath("b.JPG"), PictureFormat::kJpeg);
  EXPECT_EQ(pictureFormatFromPath("b.jpeg"), PictureFormat::kJpeg);
  const std::string error = test::errorOf([] { pictureFormatFromPath("shot.bmp"); });
  EXPECT_NE(error.find("shot.bmp"), std::string::npos) << error;
  EXPECT_NE(error.find(".jpg"), std::string::npos) << error;
  EXPECT_THROW(pictureFormatFromPath("shot"), Error);
}

TEST(ViewOptions, FrameCameraFromTheScenesIntrinsics) {
  // Record3D depth (192 x 256, f = 191.2): a tall image, 67.6 degrees high.
  const FrameCamera phone = frameCamera({191.2f, 191.2f, 95.8f, 129.4f, 192, 256});
  EXPECT_NEAR(phone.fov_y_deg, 2 * std::atan(128.0 / 191.2) * 180 / M_PI, 1e-6);
  EXPECT_NEAR(phone.aspect, 0.75, 1e-6);
  // Unknown: the Kinect the viewer assumed before scenes recorded their camera.
  const FrameCamera unknown = frameCamera(Intrinsics{});
  EXPECT_EQ(unknown.fov_y_deg, kTrajectoryFovYDeg);
  EXPECT_NEAR(unknown.aspect, 4.0 / 3.0, 1e-9);
}

TEST(SceneContent, DarkClassColoursAreLightenedForTheBackdrop) {
  auto luma = [](Rgb8 c) { return 0.2126 * c.r + 0.7152 * c.g + 0.0722 * c.b; };
  const Rgb8 black = visibleOnBackdrop({0, 0, 0, 255});
  EXPECT_NEAR(luma(black), kMinClassLuma, 1.0);
  EXPECT_EQ(black.r, black.b);  // grey stays grey
  const Rgb8 navy = visibleOnBackdrop({0, 0, 128, 255});
  EXPECT_NEAR(luma(navy), kMinClassLuma, 1.0);
  EXPECT_GT(navy.b, navy.r + 50);  // still blue
  const Rgb8 yellow{230, 200, 40, 255};
  EXPECT_EQ(visibleOnBackdrop(yellow).r, yellow.r);  // bright colours are kept as they are
  EXPECT_EQ(visibleOnBackdrop(yellow).b, yellow.b);
  ClassTable table;
  table.classes = {{0, "background", {0, 0, 0, 255}}};
  EXPECT_GE(luma(classColor(table, 0)), kMinClassLuma - 1);
}

TEST(ViewOptions, FilesBesideTheScene) {
  EXPECT_EQ(defaultTrajectoryPath("/a/b/room.vdb"), "/a/b/room.txt");
  EXPECT_EQ(besideScene("/a/b/room.vdb", "_visible.ply"), "/a/b/room_visible.ply");
}

TEST(SceneContent, ClassRowsAndPartsMatchTheSceneAndItsMesh) {
  const std::string dir = test::tempDir("viewer_content");
  const std::string path = test::writeBallScene(dir, "ball", true, true);
  const SceneContent c = loadSceneContent(path, "", true, 0.f);
  const SceneSummary summary = summarizeScene(readScene(path));
  const TriangleMesh mesh = meshScene(readScene(path));

  ASSERT_EQ(c.rows.size(), 2u);
  EXPECT_EQ(c.rows[0].name, "chair");
  EXPECT_EQ(c.rows[1].name, "table");
  EXPECT_EQ(c.rows[0].color.r, test::kChairColor.r);
  ASSERT_EQ(summary.classes.size(), 2u);
  EXPECT_EQ(c.rows[0].voxels, summary.classes[0].voxels);
  EXPECT_EQ(c.rows[1].voxels, summary.classes[1].voxels);
  EXPECT_GT(c.rows[0].voxels, 10000u);

  // Parts hold exactly the mesh's faces, split by class, with the class color per vertex.
  ASSERT_EQ(c.parts.size(), 2u);
  EXPECT_EQ(c.parts[0].mesh.triangleCount() + c.parts[1].mesh.triangleCount(), mesh.triangleCount());
  EXPECT_EQ(c.triangles, mesh.triangleCount());
  EXPECT_GT(c.parts[0].mesh.triangleCount(), 2000u);
  for (const ClassPart& part : c.parts) {
    ASSERT_EQ(part.class_colors.size(), part.mesh.vertexCount());
    const Rgb8 want = part.id == test::kClassLeft ? test::kChairColor : test::kTableColor;
    EXPECT_EQ(part.class_colors.front().g, want.g);
    size_t on_side = 0;
    for (const Vec3f& p : part.mesh.positions) on_side += part.id == test::kClassLeft ? p.x < 0.02f : p.x > -0.02f;
    EXPECT_EQ(on_side, part.mesh.vertexCount()) << "class " << part.id << " faces must lie on its half";
  }
  // Surface bounds: the floor plane spans the volume in x and z, the ball's top is at -r.
  EXPECT_NEAR(c.surface_min_m.y, -test::kBallRadius, 0.01);
  EXPECT_NEAR(c.surface_max_m.y, test::kFloorY, 0.01);

  ASSERT_EQ(c.trajectory.size(), 10u);
  EXPECT_EQ(c.trajectory_path, dir + "/ball.txt");
  EXPECT_TRUE(c.notices.empty());
}

TEST(SceneContent, WithoutClassesOnePartAndNoRows) {
  const std::string dir = test::tempDir("viewer_content_plain");
  const std::string path = test::writeBallScene(dir, "plain", false, false);
  const SceneContent c = loadSceneContent(path, "", true, 0.f);
  EXPECT_TRUE(c.rows.empty());
  ASSERT_EQ(c.parts.size(), 1u);
  EXPECT_EQ(c.parts[0].mesh.triangleCount(), c.triangles);
  EXPECT_TRUE(c.trajectory.empty());
  ASSERT_EQ(c.notices.size(), 1u);
  EXPECT_NE(c.notices[0].find("plain.txt"), std::string::npos) << c.notices[0];
  // A named trajectory that is missing is an error, not a notice.
  EXPECT_THROW(loadSceneContent(path, dir + "/missing.txt", true, 0.f), Error);
}

TEST(SceneContent, EmptySceneIsAnErrorThatSaysSo) {
  const std::string dir = test::tempDir("viewer_content_empty");
  test::SyntheticVolume volume(test::sphereSpec(32), false);
  writeScene(sceneFromBricks(volume.view(), {}), dir + "/empty.vdb");
  try {
    loadSceneContent(dir + "/empty.vdb", "", true, 0.f);
    FAIL() << "an empty scene must throw";
  } catch (const Error& e) {
    EXPECT_NE(std::string(e.what()).find("empty"), std::string::npos) << e.what();
  }
}

TEST(SceneContent, FindsClassRowsByNameOrId) {
  std::vector<ClassRow> rows{{1, "chair"}, {2, "table"}, {-1, "unknown"}};
  EXPECT_EQ(findClassRow(rows, "table"), 1);
  EXPECT_EQ(findClassRow(rows, "1"), 0);
  EXPECT_EQ(findClassRow(rows, "-1"), 2);
  EXPECT_EQ(findClassRow(rows, "sofa"), -1);
  EXPECT_EQ(findClassRow(rows, "7"), -1);
}

TEST(Slice, TsdfPlaneThroughTheBallCentreHoldsTheDistanceToTheSphere) {
  const Scene scene = test::ballOnFloorScene(true);
  const SceneSummary summary = summarizeScene(scene);
  const int k = sliceIndexAt(scene, summary, 2, 0.0f);
  const SliceImage s = sampleSlice(scene, summary, SliceGrid::kTsdf, 2, k);
  EXPECT_NEAR(s.value_m, 0.0f, 0.0051f);  // voxel centres at +-5 mm
  EXPECT_FLOAT_EQ(s.spacing_m, 0.01f);
  EXPECT_FLOAT_EQ(s.range_min, -scene.meta.truncation_m);
  EXPECT_FLOAT_EQ(s.range_max, scene.meta.truncation_m);
  ASSERT_EQ(s.values.size(), size_t(s.width) * s.height);
  // Every observed sample is the exact SDF of the ball-and-floor at its position (int16 storage).
  size_t checked = 0;
  for (int v = 0; v < s.height; ++v)
    for (int u = 0; u < s.width; ++u) {
      const float x = s.values[size_t(v) * s.width + u];
      if (!std::isfinite(x)) continue;
      const Vec3f p{s.origin_m.x + u * s.spacing_m, s.origin_m.y + v * s.spacing_m, s.origin_m.z};
      const float want = std::min(norm(p) - test::kBallRadius, test::kFloorY - p.y);
      ASSERT_NEAR(x, want, 1e-3f) << "at " << p.x << ", " << p.y;
      ++checked;
    }
  EXPECT_EQ(checked, s.observed);
  // The ball's ring: band of |sdf| < 4 voxels around a circle of 0.18 m: 2 pi r * 8 voxels.
  // Plus the floor's band across the slice. Unobserved centre stays NaN.
  EXPECT_GT(s.observed, 900u);
  const int cu = int(std::lround((0 - s.origin_m.x) / s.spacing_m)), cv = int(std::lround((0 - s.origin_m.y) / s.spacing_m));
  EXPECT_TRUE(std::isnan(s.values[size_t(cv) * s.width + cu])) << "the ball's centre was never observed";
}

TEST(Slice, WeightPlaneAndRangeErrors) {
  const Scene scene = test::ballOnFloorScene(true);
  const SceneSummary summary = summarizeScene(scene);
  const SliceImage s = sampleSlice(scene, summary, SliceGrid::kWeight, 0, sliceIndexAt(scene, summary, 0, 0.1f));
  EXPECT_EQ(s.width * s.height, int(s.values.size()));
  EXPECT_FLOAT_EQ(s.range_max, 10.f);  // fillSdf's weight
  for (float x : s.values) {
    if (std::isfinite(x)) {
      ASSERT_FLOAT_EQ(x, 10.f);
    }
  }
  EXPECT_EQ(sliceTitle(SliceGrid::kWeight), "weight [frames]");
  EXPECT_EQ(sliceTitle(SliceGrid::kTsdf), "tsdf [mm]");
  EXPECT_FLOAT_EQ(sliceDisplayScale(SliceGrid::kTsdf), 1000.f);
  try {
    sliceIndexAt(scene, summary, 2, 5.f);
    FAIL() << "a slice outside the scene must throw";
  } catch (const Error& e) {
    EXPECT_NE(std::string(e.what()).find("outside"), std::string::npos) << e.what();
    EXPECT_NE(std::string(e.what()).find("z from -0.3"), std::string::npos) << e.what();
  }
  // Moving past the end clamps to the last observed plane.
  const SliceRange r = sliceRange(scene, summary, 2);
  EXPECT_EQ(sampleSlice(scene, summary, SliceGrid::kTsdf, 2, r.last + 50).index, r.last);
}

TEST(FrustumPoses, FixedStepOrSpacedByMotion) {
  Trajectory t(10);
  for (int i = 0; i < 10; ++i) t[size_t(i)].T_world_cam.translation() = Eigen::Vector3d(0.01 * i, 0, 0);
  EXPECT_EQ(frustumPoses(t, 4, 0.0), (std::vector<size_t>{0, 4, 8, 9}));
  // 1 cm per pose, a frustum every 3 cm of motion.
  EXPECT_EQ(frustumPoses(t, 0, 0.03), (std::vector<size_t>{0, 3, 6, 9}));
  // Standing still but turning by 25 degrees at pose 5.
  Trajectory turn(8);
  for (size_t i = 5; i < 8; ++i)
    turn[i].T_world_cam.linear() = Eigen::AngleAxisd(25 * M_PI / 180, Eigen::Vector3d::UnitY()).toRotationMatrix();
  EXPECT_EQ(frustumPoses(turn, 0, 0.05), (std::vector<size_t>{0, 5, 7}));
  EXPECT_TRUE(frustumPoses({}, 0, 0.05).empty());
  EXPECT_EQ(frustumPoses(Trajectory(1), 0, 0.05), (std::vector<size_t>{0}));
}

TEST(MergeMeshes, ConcatenatesAndRenumbers) {
  TriangleMesh a, b;
  a.positions = {{0, 0, 0}, {1, 0, 0}, {0, 1, 0}};
  a.colors = {{1, 2, 3, 255}, {1, 2, 3, 255}, {1, 2, 3, 255}};
  a.classes = {1, 1, 1};
  a.triangles = {{0, 1, 2}};
  b = a;
  b.positions[0] = {5, 5, 5};
  b.classes = {2, 2, 2};
  const TriangleMesh m = mergeMeshes({&a, &b});
  ASSERT_EQ(m.vertexCount(), 6u);
  ASSERT_EQ(m.triangleCount(), 2u);
  EXPECT_EQ(m.triangles[1][0], 3);
  EXPECT_FLOAT_EQ(m.positions[3].x, 5.f);
  EXPECT_EQ(m.classes[4], 2);
  EXPECT_EQ(m.colors.size(), 6u);
  EXPECT_TRUE(m.normals.empty());
}

// In double, by atan2: acos of a float dot product cannot tell angles below 0.03 degrees.
double degreesBetween(Vec3f a, Vec3f b) {
  const Eigen::Vector3d u(a.x, a.y, a.z), v(b.x, b.y, b.z);
  return std::atan2(u.cross(v).norm(), u.dot(v)) * 180 / M_PI;
}

TEST(LevelFrame, FloorIsTheDenseLayerAtTheBottom) {
  std::vector<float> heights;
  for (int i = 0; i < 5000; ++i) heights.push_back(0.30f + 0.004f * float(i % 5 - 2));  // the floor, +-8 mm
  for (int i = 0; i < 5000; ++i) heights.push_back(0.3f + 2.5f * float(i) / 5000);     // walls up to 2.8 m
  for (int i = 0; i < 40; ++i) heights.push_back(-0.4f);                              // strays under the floor
  EXPECT_NEAR(floorHeight(heights), 0.30, 0.005);
  EXPECT_EQ(floorHeight({}), 0.0);
}

TEST(LevelFrame, PresetsAreLevelInTheScenesUpFrame) {
  // Up tilted 25 degrees from the first camera's -y and turned 40 degrees about z.
  const Eigen::Matrix3d r = test::tiltRotation(25, 40);
  const Vec3f up = test::rotated(r, {0, -1, 0}), forward = test::rotated(r, {0, 0, 1});
  const LevelFrame f = levelFrame(up, forward, {});
  EXPECT_LT(degreesBetween(f.right, test::rotated(r, {1, 0, 0})), 1e-3);
  const PresetView front = presetView(f, CameraPreset::kFront), side = presetView(f, CameraPreset::kSide),
                   top = presetView(f, CameraPreset::kTop);
  EXPECT_LT(degreesBetween(front.view_up, up), 1e-3);
  EXPECT_NEAR(degreesBetween(front.direction, up), 90, 1e-3) << "front is level";
  EXPECT_LT(degreesBetween(front.direction, forward), 1e-3) << "front looks the way the first camera did";
  EXPECT_LT(degreesBetween(side.view_up, up), 1e-3);
  EXPECT_NEAR(degreesBetween(side.direction, up), 90, 1e-3) << "side is level";
  EXPECT_NEAR(degreesBetween(side.direction, forward), 90, 1e-3) << "side is turned 90 degrees about up";
  EXPECT_LT(degreesBetween(top.direction, -up), 1e-3) << "top looks down";
  EXPECT_LT(degreesBetween(top.view_up, forward), 1e-3);
  // A slice across a world axis is faced by the preset nearest to it; a floor plan from the top.
  SliceSpec plan;
  plan.level = true;
  EXPECT_EQ(cameraFacingSlice(plan, up, forward), CameraPreset::kTop);
  SliceSpec across_z;
  across_z.axis = 2;
  EXPECT_EQ(cameraFacingSlice(across_z, {0, -1, 0}, {0, 0, 1}), CameraPreset::kFront);
  across_z.axis = 1;
  EXPECT_EQ(cameraFacingSlice(across_z, {0, -1, 0}, {0, 0, 1}), CameraPreset::kTop);
}

TEST(LevelFrame, SceneContentTakesUpFromTheSceneAndFindsItsFloor) {
  const std::string dir = test::tempDir("viewer_level_frame");
  writeScene(test::tiltedBallOnFloorScene(25, 40), dir + "/tilted.vdb");
  const SceneContent c = loadSceneContent(dir + "/tilted.vdb", "", false, 0.f);
  const Vec3f up = test::rotated(test::tiltRotation(25, 40), {0, -1, 0});
  EXPECT_LT(degreesBetween(c.frame.up, up), 0.01);
  EXPECT_EQ(c.frame.up_source, "recorded poses");
  // The floor: dot(p, up) = -kFloorY (the ball's centre at the origin, 0.22 m above it).
  EXPECT_NEAR(c.frame.floor_m, -test::kFloorY, 0.005);
  EXPECT_NEAR(c.frame.max.z - c.frame.floor_m, test::kFloorY + test::kBallRadius, 0.01) << "the ball's top";
}

// A scene written before up was recorded: estimated as exports estimate it (here from the
// floor plane under the ball), and the user is told.
TEST(LevelFrame, SceneWithoutUpGetsItEstimatedWithANotice) {
  const std::string dir = test::tempDir("viewer_level_frame_no_up");
  Scene scene = test::tiltedBallOnFloorScene(20, 0);
  const Vec3f floor_normal = scene.meta.up_world;
  scene.meta.up_world = scene.meta.forward_world = {0, 0, 0};
  scene.meta.up_source.clear();
  writeScene(scene, dir + "/old.vdb");
  const SceneContent c = loadSceneContent(dir + "/old.vdb", "", false, 0.f);
  EXPECT_LT(degreesBetween(c.frame.up, floor_normal), 2.0) << "the floor's normal, not the first camera's -y";
  ASSERT_FALSE(c.notices.empty());
  EXPECT_NE(c.notices.back().find("estimated"), std::string::npos) << c.notices.back();
  EXPECT_NE(c.frame.up_source.find("estimated"), std::string::npos) << c.frame.up_source;
}

TEST(Slice, FloorPlanIsHorizontalInTheScenesUpFrame) {
  // A floor tilted 25 degrees in the grid's axes: a plane 2 cm above it, sampled level, holds
  // tsdf = +2 cm wherever it is away from the ball; a plane tilted against the floor would not.
  const Scene scene = test::tiltedBallOnFloorScene(25, 40);
  const SceneSummary summary = summarizeScene(scene);
  MeshOptions options;
  const TriangleMesh mesh = meshScene(scene, options);
  const LevelFrame f = levelFrame(scene.meta.up_world, scene.meta.forward_world, {&mesh});
  const SliceImage s = sampleLevelSlice(scene, summary, f, SliceGrid::kTsdf, 0.02f);
  EXPECT_TRUE(s.level);
  EXPECT_LT(degreesBetween(s.normal, scene.meta.up_world), 1e-3) << "the plane's normal is up";
  EXPECT_LT(std::fabs(dot(s.u_dir, scene.meta.up_world)) + std::fabs(dot(s.v_dir, scene.meta.up_world)), 1e-5);
  size_t on_floor = 0, off = 0;
  for (int v = 0; v < s.height; ++v)
    for (int u = 0; u < s.width; ++u) {
      const float x = s.values[size_t(v) * s.width + u];
      if (!std::isfinite(x)) continue;
      const Vec3f p = s.origin_m + s.u_dir * (u * s.spacing_m) + s.v_dir * (v * s.spacing_m);
      if (norm(p) - test::kBallRadius < scene.meta.truncation_m + 0.02f) continue;  // near the ball
      ++on_floor;
      // The nearest voxel's centre lies within half a voxel's diagonal of the sample.
      off += std::fabs(x - 0.02f) > 0.0087f;
    }
  EXPECT_GT(on_floor, 1500u) << "the plane crosses the floor's band over the whole box";
  EXPECT_EQ(off, 0u) << "samples whose distance to the floor is not the plane's height";
  EXPECT_NO_THROW(requireLevelInRange(summary, f, 0.3f));
  const std::string error = test::errorOf([&] { requireLevelInRange(summary, f, 5.f); });
  EXPECT_NE(error.find("height=5 lies outside"), std::string::npos) << error;
}

}  // namespace
}  // namespace vf::viewer
