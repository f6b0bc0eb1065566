// The editor's guarantees on scenes fused from the shared real captures, not only on synthetic
// volumes: class exclusion and per-class meshes on the labelled Record3D capture, and outlier
// removal of floating blobs injected next to a fused TUM scene.
#include <gtest/gtest.h>

#include <map>
#include <tuple>

#include "brick_lookup.h"

#include "fusion/pipeline.h"
#include "io/class_table_io.h"
#include "io/labeled_source.h"
#include "io/record3d.h"
#include "io/tum_dataset.h"
#include "test_data.h"
#include "vdb/mesh_ops.h"
#include "vdb/mesher.h"
#include "vdb/scene.h"
#include "vdb/scene_edit.h"

namespace vf {
namespace {

// Fuses `frames` evenly spread frames of a source with the given poses (or ICP when none).
Scene fuse(const FrameSource& source, int frames, float voxel_m, bool with_classes, PoseSource poses,
           ClassTable classes = {}) {
  PipelineParams params;
  params.volume.voxel_size_m = voxel_m;
  Pipeline pipeline(params, source.depthIntrinsics(), Device::Cpu, with_classes);
  const int step = std::max(1, source.size() / frames);
  for (int i = 0; i < source.size() && i / step < frames; i += step) pipeline.processFrame(source.load(i), poses);
  SceneMetadata meta;
  meta.classes = std::move(classes);
  meta.frame_count = frames;
  return sceneFromBricks(pipeline.hostVolume(), meta);
}

TEST(EditorOnRealData, ExcludingPersonRemovesExactlyItsFacesAndPerClassMeshesAddUp) {
  VF_REQUIRE_DATA(capture, "record3d_dance_head200.r3d");
  VF_REQUIRE_DATA(labels, "record3d_dance_head200_labels");
  const ClassTable classes = readClassTable(labels + "/classes.json");
  const ClassInfo* person = classes.findName("person");
  ASSERT_NE(person, nullptr);
  const LabeledFrameSource source(std::make_unique<Record3dCapture>(capture), labels, classes, MissingLabels::Error);
  const Scene scene = fuse(source, 20, 0.02f, true, PoseSource::Given, classes);
  ASSERT_TRUE(scene.hasClasses());

  const TriangleMesh full = meshScene(scene);
  const std::vector<int32_t> face_class = faceClasses(full);
  std::map<int32_t, size_t> faces_per_class;
  for (int32_t c : face_class) ++faces_per_class[c];
  ASSERT_GT(faces_per_class[person->id], 1000u) << "the dancer should be in the fused scene";
  ASSERT_GT(full.triangleCount(), 20 * faces_per_class[person->id] / 10);

  const TriangleMesh without_person = filterFacesByClass(full, {person->id}, false);
  EXPECT_EQ(without_person.triangleCount(), full.triangleCount() - faces_per_class[person->id]);
  for (int32_t c : faceClasses(without_person)) EXPECT_NE(c, person->id);

  size_t per_class_total = 0;
  for (const auto& [id, part] : splitByClass(full)) {
    EXPECT_EQ(part.triangleCount(), faces_per_class[id]) << "class " << id;
    per_class_total += part.triangleCount();
  }
  EXPECT_EQ(per_class_total, full.triangleCount());
}

TEST(EditorOnRealData, OutlierRemovalDropsInjectedBlobsAndKeepsTheFusedSurface) {
  VF_REQUIRE_DATA(folder, "tum_fr3_teddy_head60");
  const TumDataset source(folder);
  PipelineParams params;
  params.volume.voxel_size_m = 3.f / 256;
  Pipeline pipeline(params, source.depthIntrinsics(), Device::Cpu);
  for (int i = 0; i < 10; ++i) pipeline.processFrame(source.load(i));
  const Scene clean = sceneFromBricks(pipeline.hostVolume(), {});
  const size_t clean_faces = meshScene(clean).triangleCount();

  // Three small floating spheres of fused-looking TSDF in empty space: new bricks, with two
  // bricks of free margin so they cannot connect to the fused surface.
  const BrickVolumeView fused = pipeline.hostVolume();
  const test::BrickLookup lookup(fused);
  HostBrickVolume v;
  v.voxel_size_m = fused.voxel_size_m;
  v.truncation_m = fused.truncation_m;
  v.coords.assign(fused.coords, fused.coords + fused.brick_count);
  v.tsdf.assign(fused.tsdf, fused.tsdf + fused.brick_count * kBrickVoxels);
  v.color.assign(fused.color, fused.color + fused.brick_count * kBrickVoxels);
  auto emptyAround = [&](const Vec3i& c) {
    for (int bz = (c.z >> 3) - 3; bz <= (c.z >> 3) + 3; ++bz)
      for (int by = (c.y >> 3) - 3; by <= (c.y >> 3) + 3; ++by)
        for (int bx = (c.x >> 3) - 3; bx <= (c.x >> 3) + 3; ++bx)
          if (lookup.hasBrick({bx, by, bz})) return false;
    return true;
  };
  std::vector<Vec3i> centres;
  for (int z = 36; z < 220 && centres.size() < 3; z += 60)
    for (int y = -92; y < 92 && centres.size() < 3; y += 60)
      for (int x = -92; x < 92 && centres.size() < 3; x += 60)
        if (emptyAround({x, y, z})) centres.push_back({x, y, z});
  ASSERT_EQ(centres.size(), 3u) << "no empty space found for the blobs";
  std::map<std::tuple<int, int, int>, size_t> added;
  for (const Vec3i& c : centres)
    for (int z = c.z - 6; z <= c.z + 6; ++z)
      for (int y = c.y - 6; y <= c.y + 6; ++y)
        for (int x = c.x - 6; x <= c.x + 6; ++x) {
          const Vec3i b = brickOfVoxel(x, y, z);
          auto [it, inserted] = added.try_emplace({b.x, b.y, b.z}, v.coords.size());
          if (inserted) {
            v.coords.push_back(b);
            v.tsdf.resize(v.tsdf.size() + kBrickVoxels, TsdfVoxel{0, 0});
            v.color.resize(v.color.size() + kBrickVoxels, Rgb8{0, 0, 0, 0});
          }
          const float r = std::sqrt(float((x - c.x) * (x - c.x) + (y - c.y) * (y - c.y) + (z - c.z) * (z - c.z)));
          const float sdf_vox = r - 3.f;
          v.tsdf[it->second * kBrickVoxels + size_t(localVoxelIndex(x, y, z))] = {
              int16_t(std::max(-1.f, std::min(1.f, sdf_vox / 5.f)) * kTsdfScale), 5};
        }
  Scene noisy = sceneFromBricks(v.view(), {});
  const size_t noisy_faces = meshScene(noisy).triangleCount();
  ASSERT_GT(noisy_faces, clean_faces + 100) << "the blobs should add surface";

  // The real scene has small noise fragments of its own, which the same removal also drops:
  // with the blobs it must remove exactly three pieces more and end with the same surface.
  OutlierOptions options;
  options.min_component_voxels = 5000;
  Scene clean_filtered = clean.clone();
  const OutlierReport clean_report = removeOutliers(clean_filtered, options);
  const OutlierReport report = removeOutliers(noisy, options);
  EXPECT_EQ(report.components_removed, clean_report.components_removed + 3);
  EXPECT_EQ(report.components_kept, clean_report.components_kept);
  EXPECT_EQ(noisy.activeVoxelCount(), clean_filtered.activeVoxelCount());
  const size_t kept_faces = meshScene(noisy).triangleCount();
  EXPECT_EQ(kept_faces, meshScene(clean_filtered).triangleCount());
  // ... and the main surface survives: most of the fused faces are still there.
  EXPECT_GT(kept_faces, clean_faces * 9 / 10);
}

}  // namespace
}  // namespace vf
