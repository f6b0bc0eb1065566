// Dense -> sparse conversion and the scene file.
#include <gtest/gtest.h>

#include <filesystem>
#include <fstream>
#include <random>

#include "core/color.h"
#include "core/error.h"
#include "synthetic_scene.h"
#include "test_data.h"
#include "vdb/scene.h"
#include "vdb/scene_info.h"

namespace vf {
namespace {

namespace fs = std::filesystem;
using test::fillSdf;
using test::sphereSdf;
using test::sphereSpec;

SceneMetadata sampleMeta() {
  SceneMetadata m;
  m.classes.classes = {{test::kClassLeft, "chair", test::kColorLeft}, {test::kClassRight, "dining table", test::kColorRight}};
  m.source = "synthetic sphere";
  m.frame_count = 42;
  return m;
}

size_t countWeighted(const test::SyntheticVolume& volume) {
  const BrickVolumeView v = volume.view();
  size_t n = 0;
  for (size_t i = 0; i < v.brick_count * kBrickVoxels; ++i) n += v.tsdf[i].weight > 0;
  return n;
}

TEST(SceneConversion, KeepsOnlyWeightedVoxelsAndTheirValues) {
  test::SyntheticVolume volume(sphereSpec(), true);
  fillSdf(volume, sphereSdf({0, 0, 0}, 0.2f), 0.f);
  const BrickVolumeView v = volume.view();
  const size_t weighted = countWeighted(volume);
  ASSERT_GT(weighted, 20000u);

  const Scene scene = sceneFromBricks(volume.view(), sampleMeta());
  EXPECT_EQ(scene.activeVoxelCount(), weighted);
  EXPECT_FLOAT_EQ(scene.meta.voxel_size_m, 0.01f);
  EXPECT_FLOAT_EQ(scene.meta.truncation_m, 0.04f);

  // Voxel (20, 0, 0) (box voxel (52, 32, 32)): centre (0.205, 0.005, 0.005), just outside the
  // sphere: sdf = 5.12 mm.
  const Vec3i on{20, 0, 0};
  const size_t i = volume.voxel(52, 32, 32);
  const SceneVoxel s = sceneVoxel(scene, on);
  ASSERT_TRUE(s.active);
  EXPECT_NEAR(s.tsdf_m, v.sdfMetres(i), 1e-6);
  EXPECT_NEAR(s.tsdf_m, 0.005122f, 2e-6);  // int16 quantisation: 1.2e-6 m
  EXPECT_FLOAT_EQ(s.weight, 10.f);
  EXPECT_EQ(s.class_id, test::kClassRight);
  EXPECT_FLOAT_EQ(s.class_confidence, 7.f);
  // sRGB 180 -> linear 0.4564; 30 -> 0.0123.
  EXPECT_NEAR(s.color_linear.y, 0.4564f, 1e-3);
  EXPECT_NEAR(s.color_linear.x, 0.0123f, 1e-3);
  // Cell-centred transform: index (20,0,0) sits where the bricks put it.
  const Vec3f c = sceneVoxelCenter(scene, on), d = volume.voxelCenter(52, 32, 32);
  EXPECT_NEAR(c.x, d.x, 1e-6);
  EXPECT_NEAR(c.y, d.y, 1e-6);
  EXPECT_NEAR(c.z, d.z, 1e-6);

  // The centre of the sphere is far from the surface: never weighted, inactive, background.
  const SceneVoxel centre = sceneVoxel(scene, {0, 0, 0});
  EXPECT_FALSE(centre.active);
  EXPECT_FLOAT_EQ(centre.tsdf_m, 0.04f);
  EXPECT_EQ(centre.class_id, kSceneUnknownClass);
}

TEST(SceneConversion, UnknownClassVoteBecomesMinusOneAndBricksWithoutWeightAreSkipped) {
  test::SyntheticVolume volume(sphereSpec(32), true);
  HostBrickVolume& v = volume.bricks();
  // Box voxel (x, y, z) is global voxel (x - 16, y - 16, z - 16).
  const size_t a = volume.voxel(3, 4, 5);
  v.tsdf[a] = {1000, 3};
  v.class_vote[a] = packClassVote(kUnknownClass, 0);
  volume.voxel(20, 20, 20);  // allocated, never weighted: the brick is not converted
  // Fused geometry that no label ever voted on keeps the zero-initialised vote: class unknown,
  // not class 0 (which a table may well define, e.g. "background").
  const size_t never_voted = volume.voxel(4, 4, 5);
  v.tsdf[never_voted] = {1000, 3};
  const Scene scene = sceneFromBricks(volume.view(), {});
  EXPECT_EQ(scene.activeVoxelCount(), 2u);
  EXPECT_EQ(sceneVoxel(scene, {-12, -12, -11}).class_id, kSceneUnknownClass);
  EXPECT_EQ(sceneVoxel(scene, {-13, -12, -11}).class_id, kSceneUnknownClass);
  EXPECT_TRUE(sceneVoxel(scene, {-13, -12, -11}).active);
  EXPECT_FALSE(sceneVoxel(scene, {4, 4, 4}).active);
}

TEST(SceneFile, RoundTripKeepsGridsCountsAndMetadata) {
  test::SyntheticVolume volume(sphereSpec(), true);
  fillSdf(volume, sphereSdf({0, 0, 0}, 0.2f), 0.f);
  const Scene scene = sceneFromBricks(volume.view(), sampleMeta());
  const std::string dir = test::tempDir("scene_roundtrip");
  const std::string path = dir + "/scene.vdb";
  writeScene(scene, path);
  EXPECT_EQ(std::distance(fs::directory_iterator(dir), fs::directory_iterator()), 1) << "temp file left";

  const Scene back = readScene(path);
  const SceneSummary a = summarizeScene(scene), b = summarizeScene(back);
  ASSERT_EQ(a.grids.size(), 5u);
  ASSERT_EQ(b.grids.size(), 5u);
  for (size_t i = 0; i < a.grids.size(); ++i) {
    EXPECT_EQ(a.grids[i].name, b.grids[i].name);
    EXPECT_EQ(a.grids[i].active_voxels, b.grids[i].active_voxels);
  }
  EXPECT_EQ(back.activeVoxelCount(), scene.activeVoxelCount());
  EXPECT_FLOAT_EQ(back.meta.voxel_size_m, 0.01f);
  EXPECT_FLOAT_EQ(back.meta.truncation_m, 0.04f);
  EXPECT_EQ(back.meta.source, "synthetic sphere");
  EXPECT_EQ(back.meta.frame_count, 42);
  EXPECT_FALSE(back.meta.software_version.empty());
  ASSERT_EQ(back.meta.classes.classes.size(), 2u);
  EXPECT_EQ(back.meta.classes.findId(2)->name, "dining table");
  EXPECT_EQ(back.meta.classes.findId(2)->color.g, 180);
  ASSERT_EQ(a.classes.size(), b.classes.size());
  for (size_t i = 0; i < a.classes.size(); ++i) EXPECT_EQ(a.classes[i].voxels, b.classes[i].voxels);
  EXPECT_NEAR(sceneVoxel(back, {20, 0, 0}).tsdf_m, 0.005122f, 2e-6);
  // Bounds: the band reaches 0.2 + 0.04 m from the centre, to within a voxel.
  EXPECT_NEAR(b.bounds_max_m.x, 0.24f, 0.011f);
  EXPECT_NEAR(b.bounds_min_m.y, -0.24f, 0.011f);
}

bool sameVoxel(const SceneVoxel& a, const SceneVoxel& b) {
  return a.active == b.active && a.tsdf_m == b.tsdf_m && a.weight == b.weight && a.class_id == b.class_id &&
         a.class_confidence == b.class_confidence && a.color_linear.x == b.color_linear.x &&
         a.color_linear.y == b.color_linear.y && a.color_linear.z == b.color_linear.z;
}

// The streaming writer must give the scene writeScene gives: the same grids, voxel for voxel,
// and the same metadata. (The files differ only in the random UUID and in the optional
// delayed-load index libopenvdb adds, which the streamed file leaves out.)
void expectStreamedSceneEqualsInMemoryScene(const test::SyntheticVolume& volume, const std::string& name) {
  const std::string dir = test::tempDir("scene_stream_" + name);
  SceneMetadata meta = sampleMeta();
  meta.up_world = {0, -1, 0};
  meta.forward_world = {0, 0, 1};
  meta.up_source = "camera up-vectors";
  writeScene(sceneFromBricks(volume.view(), meta), dir + "/memory.vdb");
  writeSceneFromBricks(volume.view(), meta, dir + "/streamed.vdb");
  EXPECT_EQ(std::distance(fs::directory_iterator(dir), fs::directory_iterator()), 2) << "temp file left";
  const Scene a = readScene(dir + "/memory.vdb"), b = readScene(dir + "/streamed.vdb");
  ASSERT_EQ(b.activeVoxelCount(), countWeighted(volume));
  ASSERT_EQ(a.activeVoxelCount(), b.activeVoxelCount());
  const SceneSummary sa = summarizeScene(a), sb = summarizeScene(b);
  ASSERT_EQ(sa.grids.size(), sb.grids.size());
  for (size_t i = 0; i < sa.grids.size(); ++i) {
    EXPECT_EQ(sa.grids[i].name, sb.grids[i].name);
    EXPECT_EQ(sa.grids[i].active_voxels, sb.grids[i].active_voxels);
  }
  EXPECT_EQ(b.meta.source, a.meta.source);
  EXPECT_EQ(b.meta.frame_count, a.meta.frame_count);
  EXPECT_EQ(b.meta.up_source, a.meta.up_source);
  EXPECT_FLOAT_EQ(b.meta.up_world.y, -1.f);
  EXPECT_EQ(b.meta.classes.classes.size(), a.meta.classes.classes.size());
  EXPECT_FLOAT_EQ(b.meta.truncation_m, a.meta.truncation_m);
  // Every voxel, active or not, of every third allocated brick (all of them take seconds).
  const BrickVolumeView v = volume.view();
  size_t differing = 0;
  for (size_t n = 0; n < v.brick_count; n += 3)
    for (int i = 0; i < kBrickVoxels; ++i) {
      const Vec3i l = localVoxelOffset(i), c = v.coords[n];
      const Vec3i voxel{c.x * kBrickSize + l.x, c.y * kBrickSize + l.y, c.z * kBrickSize + l.z};
      differing += !sameVoxel(sceneVoxel(a, voxel), sceneVoxel(b, voxel));
    }
  EXPECT_EQ(differing, 0u);
}

TEST(SceneFile, StreamedFromBricksIsTheSameFileAsWrittenFromGrids) {
  // Many bricks (several write batches) spread over several root nodes, negative coordinates
  // included, random values and votes; a sphere for realistic leaves.
  for (const bool with_classes : {true, false}) {
    test::SyntheticVolume volume(sphereSpec(), with_classes);
    fillSdf(volume, sphereSdf({0, 0, 0}, 0.2f), 0.f);
    HostBrickVolume& v = volume.bricks();
    std::mt19937 rng(7);
    // +-700 voxels: 8 root nodes around the origin (each spans 4096 voxels).
    std::uniform_int_distribution<int> coord(-700, 700), value(-32767, 32767), weight(0, 3), byte(0, 255);
    for (int n = 0; n < 12000; ++n) {
      const size_t i = volume.voxel(coord(rng), coord(rng), coord(rng));
      v.tsdf[i] = {int16_t(value(rng)), uint16_t(weight(rng))};
      v.color[i] = {uint8_t(byte(rng)), uint8_t(byte(rng)), uint8_t(byte(rng)), 1};
      if (with_classes) v.class_vote[i] = packClassVote(uint32_t(byte(rng) % 4), uint32_t(byte(rng) % 3));
    }
    expectStreamedSceneEqualsInMemoryScene(volume, with_classes ? "classes" : "plain");
  }
}

TEST(SceneFile, HalfFloatStorageKeepsEveryColourByteEveryCountAndTheTsdfToAHalfStep) {
  // The float grids are saved as half floats. What a scene holds must survive that: every sRGB
  // byte of the fused colour (through the linear grid and back), observation counts up to 2048,
  // and the TSDF to within half a half-float step, 2^-11 of its value: at most 2^-11 of the
  // truncation (14 um at the default 29 mm; the bricks hold 0.9 um steps).
  test::SyntheticVolume volume(sphereSpec(), true);
  HostBrickVolume& v = volume.bricks();
  std::mt19937 rng(11);
  std::uniform_int_distribution<int> value(-32767, 32767);
  struct Written {
    Vec3i voxel;
    TsdfVoxel tsdf;
    Rgb8 color;
  };
  std::vector<Written> written;
  for (int n = 0; n < 2049; ++n) {
    const int x = n % 64, y = (n / 64) % 16, z = n / 1024;
    const size_t i = volume.voxel(x, y, z);
    const uint8_t c = uint8_t(n % 256);
    v.tsdf[i] = {int16_t(value(rng)), uint16_t(n == 0 ? 2048 : n)};
    v.color[i] = {c, uint8_t(255 - c), uint8_t((c * 7) % 256), 1};
    v.class_vote[i] = packClassVote(uint32_t(n % 5), uint32_t(n % 256));
    written.push_back({volume.global(x, y, z), v.tsdf[i], v.color[i]});
  }
  const std::string dir = test::tempDir("scene_half");
  writeSceneFromBricks(volume.view(), sampleMeta(), dir + "/scene.vdb");
  const Scene back = readScene(dir + "/scene.vdb");
  const float trunc = volume.spec().truncation_m;
  size_t colour_bytes_changed = 0, counts_changed = 0;
  float worst_tsdf_m = 0.f;
  for (const Written& w : written) {
    const SceneVoxel got = sceneVoxel(back, w.voxel);
    ASSERT_TRUE(got.active);
    const Rgb8 srgb = linearToSrgb8(got.color_linear);
    colour_bytes_changed += (srgb.r != w.color.r) + (srgb.g != w.color.g) + (srgb.b != w.color.b);
    counts_changed += got.weight != float(w.tsdf.weight);
    worst_tsdf_m = std::max(worst_tsdf_m, std::fabs(got.tsdf_m - float(w.tsdf.tsdf) * (trunc / kTsdfScale)));
  }
  EXPECT_EQ(colour_bytes_changed, 0u);
  EXPECT_EQ(counts_changed, 0u);
  EXPECT_GT(worst_tsdf_m, trunc / 65536.f) << "not a half float's rounding: stored as full floats?";
  EXPECT_LE(worst_tsdf_m, trunc / 2048.f);
}

TEST(SceneFile, TruncatedForeignAndIncompleteFilesAreClearErrors) {
  test::SyntheticVolume volume(sphereSpec(), false);
  fillSdf(volume, sphereSdf({0, 0, 0}, 0.2f), 0.f);
  const Scene scene = sceneFromBricks(volume.view(), {});
  const std::string dir = test::tempDir("scene_bad_files");
  writeScene(scene, dir + "/good.vdb");
  const auto size = fs::file_size(dir + "/good.vdb");
  fs::copy_file(dir + "/good.vdb", dir + "/cut.vdb");
  fs::resize_file(dir + "/cut.vdb", size / 2);
  EXPECT_THROW(readScene(dir + "/cut.vdb"), Error);

  std::ofstream(dir + "/random.vdb", std::ios::binary) << std::string(4096, '\x5a');
  EXPECT_THROW(readScene(dir + "/random.vdb"), Error);
  EXPECT_THROW(readScene(dir + "/missing.vdb"), Error);

  EXPECT_NO_THROW(readScene(dir + "/good.vdb"));
  // (A VDB without `tsdf` -- the Blender fog volume -- is checked in export_test.)
  try {
    readScene(dir + "/cut.vdb");
  } catch (const Error& e) {
    EXPECT_NE(std::string(e.what()).find("cut.vdb"), std::string::npos) << e.what();
  }
}

}  // namespace
}  // namespace vf

namespace vf {
namespace {

// `info` reads only the headers (issue 37): the counts, bounds and metadata there must be what
// reading the whole scene finds, for both writers.
void expectHeaderMatchesFullRead(const std::string& path) {
  SCOPED_TRACE(path);
  const SceneHeader h = readSceneHeader(path);
  ASSERT_TRUE(h.statistics_recorded);
  const Scene scene = readScene(path);
  const SceneSummary full = summarizeScene(scene);
  ASSERT_EQ(h.summary.grids.size(), full.grids.size());
  for (size_t i = 0; i < full.grids.size(); ++i) {
    EXPECT_EQ(h.summary.grids[i].name, full.grids[i].name);
    EXPECT_EQ(h.summary.grids[i].value_type, full.grids[i].value_type);
    EXPECT_EQ(h.summary.grids[i].active_voxels, full.grids[i].active_voxels);
    // The size the grid had in memory when written; read back it is the same structure.
    EXPECT_NEAR(double(h.summary.grids[i].memory_bytes), double(full.grids[i].memory_bytes),
                0.05 * double(full.grids[i].memory_bytes));
  }
  EXPECT_EQ(h.summary.active_voxels, full.active_voxels);
  EXPECT_GT(h.summary.active_voxels, 10000u);
  EXPECT_FALSE(h.summary.empty);
  for (const auto& [a, b] : {std::pair{h.summary.bounds_min_m, full.bounds_min_m}, {h.summary.bounds_max_m, full.bounds_max_m}}) {
    EXPECT_FLOAT_EQ(a.x, b.x);
    EXPECT_FLOAT_EQ(a.y, b.y);
    EXPECT_FLOAT_EQ(a.z, b.z);
  }
  EXPECT_EQ(h.summary.surface_voxels, 0u) << "the surface needs the voxels: left to summarizeScene";
  EXPECT_TRUE(h.summary.classes.empty());
  EXPECT_EQ(h.has_classes, scene.hasClasses());
  EXPECT_EQ(h.meta.source, scene.meta.source);
  EXPECT_EQ(h.meta.frame_count, scene.meta.frame_count);
  EXPECT_FLOAT_EQ(h.meta.voxel_size_m, scene.meta.voxel_size_m);
  EXPECT_FLOAT_EQ(h.meta.truncation_m, scene.meta.truncation_m);
  EXPECT_EQ(h.meta.classes.classes.size(), scene.meta.classes.classes.size());
  EXPECT_EQ(h.meta.up_source, scene.meta.up_source);
  EXPECT_FLOAT_EQ(h.meta.up_world.y, scene.meta.up_world.y);
}

TEST(SceneHeader, CountsAndBoundsFromTheHeadersMatchTheVoxels) {
  for (const bool with_classes : {true, false}) {
    test::SyntheticVolume volume(sphereSpec(), with_classes);
    fillSdf(volume, sphereSdf({0.05f, 0, 0}, 0.2f), 0.f);
    SceneMetadata meta = sampleMeta();
    if (!with_classes) meta.classes = {};
    meta.up_world = {0, -1, 0};
    meta.forward_world = {0, 0, 1};
    meta.up_source = "floor plane";
    const std::string dir = test::tempDir(std::string("scene_header_") + (with_classes ? "classes" : "plain"));
    writeScene(sceneFromBricks(volume.view(), meta), dir + "/memory.vdb");
    writeSceneFromBricks(volume.view(), meta, dir + "/streamed.vdb");
    expectHeaderMatchesFullRead(dir + "/memory.vdb");
    expectHeaderMatchesFullRead(dir + "/streamed.vdb");
  }
}

// Timing-free proof that no tree is read: the last grid's leaf values are overwritten with
// garbage. Reading the scene fails on them; the header reader never looks there.
TEST(SceneHeader, DoesNotReadTheVoxelTrees) {
  test::SyntheticVolume volume(sphereSpec(), true);
  fillSdf(volume, sphereSdf({0, 0, 0}, 0.2f), 0.f);
  const std::string dir = test::tempDir("scene_header_trees");
  const std::string path = dir + "/scene.vdb";
  writeScene(sceneFromBricks(volume.view(), sampleMeta()), path);
  const SceneHeader before = readSceneHeader(path);
  const uintmax_t size = fs::file_size(path);
  {
    std::fstream f(path, std::ios::in | std::ios::out | std::ios::binary);
    const std::string garbage(4096, '\xA5');
    f.seekp(std::streamoff(size - garbage.size() - 64));  // inside class_confidence's leaf buffers
    f.write(garbage.data(), std::streamsize(garbage.size()));
  }
  ASSERT_EQ(fs::file_size(path), size);
  EXPECT_THROW(readScene(path), Error) << "the damage must lie in the voxel data";
  const SceneHeader after = readSceneHeader(path);
  EXPECT_EQ(after.summary.active_voxels, before.summary.active_voxels);
  EXPECT_EQ(after.summary.grids.size(), 5u);
  EXPECT_EQ(after.meta.classes.classes.size(), 2u);
}

TEST(SceneHeader, DamagedHeadersAndForeignFilesAreClearErrors) {
  const std::string dir = test::tempDir("scene_header_errors");
  const std::string missing = test::errorOf([&] { readSceneHeader(dir + "/none.vdb"); });
  EXPECT_NE(missing.find(dir + "/none.vdb"), std::string::npos) << missing;
  std::ofstream(dir + "/junk.vdb") << "not an OpenVDB file";
  const std::string junk = test::errorOf([&] { readSceneHeader(dir + "/junk.vdb"); });
  EXPECT_NE(junk.find(dir + "/junk.vdb"), std::string::npos) << junk;
}

}  // namespace
}  // namespace vf
