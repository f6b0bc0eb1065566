// Scene edits (class removal, crop, outliers, smoothing) and the grid-level exports.
#include <gtest/gtest.h>

#include <cmath>

#include "core/error.h"
#include "synthetic_scene.h"
#include "test_data.h"
#include "vdb/mesh_ops.h"
#include "vdb/mesher.h"
#include "vdb/scene.h"
#include "vdb/scene_edit.h"
#include "vdb/scene_grids.h"
#include "vdb/scene_export.h"
#include "vdb/scene_info.h"

namespace vf {
namespace {

using test::fillSdf;
using test::sphereSdf;
using test::sphereSpec;

constexpr float kRadius = 0.2f, kVoxel = 0.01f;

Scene sphereScene(bool with_blobs, uint16_t blob_weight = 10) {
  test::SyntheticVolume volume(sphereSpec(), true);
  fillSdf(volume, sphereSdf({0, 0, 0}, kRadius), 0.f);
  if (with_blobs) {  // three floating blobs of ~0.025 m, well away from the sphere
    fillSdf(volume, sphereSdf({0.25f, 0.25f, 0.25f}, 0.025f), 0.f, blob_weight);
    fillSdf(volume, sphereSdf({-0.25f, 0.25f, -0.25f}, 0.025f), 0.f, blob_weight);
    fillSdf(volume, sphereSdf({0.25f, -0.25f, 0.25f}, 0.02f), 0.f, blob_weight);
  }
  SceneMetadata meta;
  meta.classes.classes = {{test::kClassLeft, "chair", {255, 0, 0, 255}}, {test::kClassRight, "table", {0, 0, 255, 255}}};
  return sceneFromBricks(volume.view(), meta);
}

size_t classVoxels(const Scene& scene, int id) {
  for (const ClassVoxelCount& c : summarizeScene(scene).classes)
    if (c.id == id) return c.voxels;
  return 0;
}

TEST(SceneEdit, ExcludeClassRemovesExactlyItsVoxels) {
  Scene scene = sphereScene(false);
  const size_t left = classVoxels(scene, test::kClassLeft), total = scene.activeVoxelCount();
  ASSERT_GT(left, 10000u);
  EXPECT_EQ(excludeClassVoxels(scene, {test::kClassLeft}), left);
  EXPECT_EQ(scene.activeVoxelCount(), total - left);
  EXPECT_EQ(classVoxels(scene, test::kClassLeft), 0u);
  // Every grid keeps the tsdf's topology.
  for (const GridSummary& g : summarizeScene(scene).grids) EXPECT_EQ(g.active_voxels, total - left) << g.name;
  for (const Vec3f& p : meshScene(scene).positions) EXPECT_GT(p.x, -kVoxel);
}

TEST(SceneEdit, CropKeepsOnlyVoxelsInsideTheBox) {
  Scene scene = sphereScene(false);
  const size_t removed = cropToBox(scene, {-1, -1, 0.0f}, {1, 1, 1});
  EXPECT_GT(removed, 0u);
  const SceneSummary s = summarizeScene(scene);
  EXPECT_NEAR(s.bounds_min_m.z, 0.0f, 1e-5);  // first kept voxel centre z = 0.005
  EXPECT_NEAR(s.bounds_max_m.z, 0.24f, kVoxel + 1e-5);
  EXPECT_THROW(cropToBox(scene, {0, 0, 0}, {0, 1, 1}), Error);
}

// A box given in a rotated frame (as an export's Z-up) keeps exactly the voxels whose centres,
// taken into that frame, lie inside it: here a slab tilted 30 degrees about x.
TEST(SceneEdit, CropInARotatedFrameKeepsWhatThatFrameShowsInsideTheBox) {
  Scene scene = sphereScene(false);
  const float c = std::cos(0.5236f), s = std::sin(0.5236f);
  const Rigid3f box_from_scene{{1, 0, 0, 0, c, -s, 0, s, c}, {0, 0, 0.05f}};
  const Vec3f lo{-1, -1, 0.f}, hi{1, 1, 1};
  const auto inside = [&](const openvdb::Vec3d& w) {
    const Vec3f p = box_from_scene * Vec3f{float(w.x()), float(w.y()), float(w.z())};
    return p.x >= lo.x && p.y >= lo.y && p.z >= lo.z && p.x <= hi.x && p.y <= hi.y && p.z <= hi.z;
  };
  const openvdb::FloatGrid& tsdf = *scene.grids().tsdf;
  size_t expected_kept = 0;
  for (auto it = tsdf.cbeginValueOn(); it; ++it) expected_kept += inside(tsdf.transform().indexToWorld(it.getCoord()));
  const size_t before = scene.activeVoxelCount();
  ASSERT_GT(expected_kept, before / 4);
  ASSERT_LT(expected_kept, before * 3 / 4);
  EXPECT_EQ(cropToBox(scene, lo, hi, box_from_scene), before - expected_kept);
  EXPECT_EQ(scene.activeVoxelCount(), expected_kept);
  for (auto it = scene.grids().tsdf->cbeginValueOn(); it; ++it)
    ASSERT_TRUE(inside(tsdf.transform().indexToWorld(it.getCoord())));
  // The axis-aligned box of the scene's own frame keeps a different set.
  Scene plain = sphereScene(false);
  EXPECT_NE(before - cropToBox(plain, lo, hi), expected_kept);
}

// info's "surface z-up": the surface voxels' centres in the frame it is given.
TEST(SceneInfo, SurfaceBoundsAreTakenInTheGivenFrame) {
  const Scene scene = sphereScene(false);
  const SceneSummary own = summarizeScene(scene);
  for (float v : {own.surface_min_m.x, own.surface_min_m.y, own.surface_min_m.z}) EXPECT_NEAR(v, -kRadius, kVoxel);
  for (float v : {own.surface_max_m.x, own.surface_max_m.y, own.surface_max_m.z}) EXPECT_NEAR(v, kRadius, kVoxel);
  // x -> y, y -> -x, then 1 m up z: the sphere's box moves and turns with it.
  const SceneSummary turned = summarizeScene(scene, Rigid3f{{0, -1, 0, 1, 0, 0, 0, 0, 1}, {0, 0, 1}});
  EXPECT_NEAR(turned.surface_min_m.x, -own.surface_max_m.y, 1e-5f);
  EXPECT_NEAR(turned.surface_max_m.y, own.surface_max_m.x, 1e-5f);
  EXPECT_NEAR(turned.surface_min_m.z, own.surface_min_m.z + 1.f, 1e-5f);
  EXPECT_EQ(turned.surface_voxels, own.surface_voxels);
}

TEST(SceneEdit, OutlierRemovalDeletesFloatingBlobsAndKeepsTheSurface) {
  const TriangleMesh clean = meshScene(sphereScene(false));
  Scene scene = sphereScene(true);
  ASSERT_GT(meshScene(scene).triangleCount(), clean.triangleCount() + 300);
  OutlierOptions options;
  options.min_component_triangles = 500;
  const OutlierReport r = removeOutliers(scene, options);
  EXPECT_EQ(r.pieces_before, 4u);
  EXPECT_EQ(r.small_pieces_before, 3u);
  EXPECT_EQ(r.pieces_after, 1u);
  EXPECT_EQ(r.small_pieces_after, 0u);
  EXPECT_EQ(r.passes, 1);
  // The blobs' whole band goes, not only their surface: nothing of them is left for a volume.
  EXPECT_EQ(scene.activeVoxelCount(), sphereScene(false).activeVoxelCount());
  EXPECT_GT(r.bare_band_voxels, 0u);
  const TriangleMesh after = meshScene(scene);
  EXPECT_EQ(meshComponents(after, 500).small, 0u);
  EXPECT_NEAR(double(after.triangleCount()), double(clean.triangleCount()), 0.01 * clean.triangleCount());
  for (const Vec3f& p : after.positions) EXPECT_NEAR(norm(p), kRadius, kVoxel);
}

TEST(SceneEdit, WeaklyObservedVoxelsGoBelowTheWeight) {
  Scene scene = sphereScene(true, /*blob_weight=*/1);
  const size_t before = scene.activeVoxelCount();
  OutlierOptions options;
  options.min_weight = 2;
  const OutlierReport r = removeOutliers(scene, options);
  EXPECT_GT(r.weak_voxels, 1000u);
  EXPECT_EQ(scene.activeVoxelCount(), before - r.weak_voxels);
  for (const Vec3f& p : meshScene(scene).positions) EXPECT_NEAR(norm(p), kRadius, kVoxel);
}

TEST(SceneEdit, SmoothingKeepsTheSphereAndTheActiveSet) {
  Scene scene = sphereScene(false);
  const size_t active = scene.activeVoxelCount();
  const size_t changed = smoothScene(scene, 2);
  EXPECT_GT(changed, 1000u);
  EXPECT_EQ(scene.activeVoxelCount(), active);
  const TriangleMesh mesh = meshScene(scene);
  // Mean-curvature flow shrinks a sphere slowly; two steps move it far less than a voxel.
  for (const Vec3f& p : mesh.positions) EXPECT_NEAR(norm(p), kRadius, kVoxel);
  EXPECT_GT(mesh.triangleCount(), 5000u);
}

TEST(SceneExport, BlenderVolumeHasDensityAndColorAndIsNotAScene) {
  const Scene scene = sphereScene(false);
  const std::string dir = test::tempDir("blender_volume");
  writeBlenderVolume(scene, dir + "/volume.vdb");
  const std::vector<std::string> names = vdbGridNames(dir + "/volume.vdb");
  EXPECT_EQ(names, (std::vector<std::string>{"color", "density"}));  // listed by name
  EXPECT_THROW(readScene(dir + "/volume.vdb"), Error);  // a .vdb without `tsdf`
  try {
    readScene(dir + "/volume.vdb");
  } catch (const Error& e) {
    EXPECT_NE(std::string(e.what()).find("no 'tsdf' grid"), std::string::npos) << e.what();
  }
  // The scene itself re-reads with its five grids.
  writeScene(scene, dir + "/scene.vdb");
  EXPECT_EQ(vdbGridNames(dir + "/scene.vdb"),
            (std::vector<std::string>{"class", "class_confidence", "color", "tsdf", "weight"}));
}

TEST(SceneExport, PointCloudLiesOnTheSurfaceWithColors) {
  const Scene scene = sphereScene(false);
  const TriangleMesh cloud = scenePointCloud(scene);
  ASSERT_GT(cloud.vertexCount(), 3000u);
  EXPECT_EQ(cloud.triangleCount(), 0u);
  for (size_t i = 0; i < cloud.vertexCount(); ++i) {
    EXPECT_NEAR(norm(cloud.positions[i]), kRadius, 0.25f * kVoxel);
    if (cloud.positions[i].x > 1.5f * kVoxel) {
      EXPECT_EQ(cloud.colors[i].g, 180);
    }
  }
  MeshOptions by_class;
  by_class.color = MeshColorMode::kClass;
  const TriangleMesh classed = scenePointCloud(scene, by_class);
  for (size_t i = 0; i < classed.vertexCount(); ++i) {
    if (classed.positions[i].x < -1.5f * kVoxel) {
      EXPECT_EQ(classed.colors[i].r, 255);
    }
  }
}

}  // namespace
}  // namespace vf
