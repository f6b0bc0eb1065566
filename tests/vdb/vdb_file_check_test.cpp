// The structural .vdb check that runs before libopenvdb (src/vdb/vdb_file_check.h): it must walk
// every file libopenvdb writes to the byte, and turn damaged ones into vf::Error before
// libopenvdb allocates what they claim.
#include <gtest/gtest.h>

#include <cstring>
#include <filesystem>
#include <fstream>
#include <iterator>
#include <openvdb/io/File.h>
#include <random>

#include "core/error.h"
#include "test_data.h"
#include "vdb/scene.h"
#include "vdb/scene_grids.h"
#include "vdb/scene_info.h"
#include "vdb/vdb_file_check.h"

namespace vf {
namespace {

namespace fs = std::filesystem;

const std::vector<std::string> kGridNames = {"tsdf", "color", "class"};

// Grids with what a tree can hold: several root children, leaves with active and inactive
// voxels, dense leaves, inactive and active tiles at every level, negative coordinates.
openvdb::GridPtrVec makeGrids() {
  auto tsdf = openvdb::FloatGrid::create(0.04f);
  tsdf->setName("tsdf");
  tsdf->setGridClass(openvdb::GRID_LEVEL_SET);
  auto color = openvdb::Vec3SGrid::create(openvdb::Vec3s(0));
  color->setName("color");
  auto cls = openvdb::Int32Grid::create(-1);
  cls->setName("class");
  std::mt19937 rng(7);
  std::uniform_int_distribution<int> coord(-300, 300);
  std::uniform_real_distribution<float> value(-0.04f, 0.04f);
  auto t = tsdf->getAccessor();
  auto c = color->getAccessor();
  auto k = cls->getAccessor();
  for (int i = 0; i < 4000; ++i) {
    const openvdb::Coord p(coord(rng), coord(rng), coord(rng) / 10);
    t.setValue(p, value(rng));
    c.setValue(p, openvdb::Vec3s(value(rng), 0.5f, 1.f));
    k.setValue(p, i % 7);
    if (i % 3 == 0) t.setValueOff(p.offsetBy(1, 0, 0), -0.04f);  // inactive inside value
  }
  tsdf->fill(openvdb::CoordBBox({-64, -64, 8}, {-1, -1, 15}), -0.02f, true);   // dense leaves
  tsdf->tree().addTile(1, openvdb::Coord(1024, 0, 0), -0.04f, false);          // inactive tile
  tsdf->tree().addTile(2, openvdb::Coord(0, 4096, 0), 0.01f, true);            // active tile
  cls->tree().addTile(3, openvdb::Coord(-8192, 0, 0), 3, true);                // root tile
  return {tsdf, color, cls};
}

std::string writeGrids(const fs::path& dir, const std::string& name, uint32_t compression, bool half) {
  openvdb::GridPtrVec grids = makeGrids();
  for (auto& g : grids) g->setSaveFloatAsHalf(half);
  const std::string path = (dir / name).string();
  openvdb::io::File file(path);
  file.setCompression(compression);
  file.write(grids);
  file.close();
  return path;
}

std::vector<char> readBytes(const std::string& path) {
  std::ifstream f(path, std::ios::binary);
  return {std::istreambuf_iterator<char>(f), std::istreambuf_iterator<char>()};
}

void writeBytes(const std::string& path, const std::vector<char>& bytes) {
  std::ofstream(path, std::ios::binary).write(bytes.data(), std::streamsize(bytes.size()));
}

class VdbFileCheck : public ::testing::Test {
 protected:
  void SetUp() override {
    ensureOpenVdbInitialized();
    dir_ = test::tempDir("vdb_file_check");
  }
  fs::path dir_;  // fresh per test
};

TEST_F(VdbFileCheck, WalksEveryCompressionAndHalfFloatToTheByte) {
  using openvdb::io::COMPRESS_ACTIVE_MASK;
  using openvdb::io::COMPRESS_BLOSC;
  using openvdb::io::COMPRESS_ZIP;
  const uint32_t settings[] = {openvdb::io::COMPRESS_NONE, COMPRESS_ZIP, COMPRESS_ACTIVE_MASK, COMPRESS_BLOSC,
                               COMPRESS_ZIP | COMPRESS_ACTIVE_MASK, COMPRESS_BLOSC | COMPRESS_ACTIVE_MASK};
  for (const uint32_t compression : settings) {
    for (const bool half : {false, true}) {
      SCOPED_TRACE("compression " + std::to_string(compression) + (half ? " half" : " full"));
      const std::string path = writeGrids(dir_, "grids.vdb", compression, half);
      const VdbFileWalk walk = checkVdbFileStructure(path, kGridNames);
      EXPECT_EQ(walk.grids_checked, 3);
      EXPECT_EQ(walk.grids_ending_at_stated_end, 3);
    }
  }
}

// Below 128 bytes libopenvdb pads the delayed-load arrays it keeps per leaf before compressing
// them: a grid of a few leaves has such metadata.
TEST_F(VdbFileCheck, WalksGridsOfAFewLeaves) {
  for (const int leaves : {1, 7, 60, 200}) {
    SCOPED_TRACE(std::to_string(leaves) + " leaves");
    auto tsdf = openvdb::FloatGrid::create(0.04f);
    tsdf->setName("tsdf");
    for (int i = 0; i < leaves; ++i) tsdf->tree().setValue(openvdb::Coord(8 * i, 0, 0), 0.01f);
    const std::string path = (dir_ / "few.vdb").string();
    openvdb::io::File file(path);
    file.write({tsdf});
    file.close();
    const VdbFileWalk walk = checkVdbFileStructure(path, kGridNames);
    EXPECT_EQ(walk.grids_checked, 1);
    EXPECT_EQ(walk.grids_ending_at_stated_end, 1);
  }
}

TEST_F(VdbFileCheck, WalksAScene) {
  const std::string path = (dir_ / "scene.vdb").string();
  Scene scene;
  openvdb::GridPtrVec grids = makeGrids();
  scene.grids().tsdf = openvdb::gridPtrCast<openvdb::FloatGrid>(grids[0]);
  scene.grids().tsdf->setTransform(openvdb::math::Transform::createLinearTransform(0.01));  // as the metadata says
  scene.grids().weight = scene.grids().tsdf->deepCopy();
  scene.grids().weight->setName("weight");
  scene.grids().weight->setGridClass(openvdb::GRID_UNKNOWN);
  scene.meta.voxel_size_m = 0.01f;
  writeScene(scene, path);
  const VdbFileWalk walk = checkVdbFileStructure(path, {"tsdf", "weight", "color", "class"});
  EXPECT_EQ(walk.grids_checked, 2);
  EXPECT_EQ(walk.grids_ending_at_stated_end, 2);
  EXPECT_EQ(readScene(path).activeVoxelCount(), scene.activeVoxelCount());
}

TEST_F(VdbFileCheck, RejectsTruncationAnywhere) {
  const std::string good = writeGrids(dir_, "good.vdb", openvdb::io::COMPRESS_BLOSC | openvdb::io::COMPRESS_ACTIVE_MASK,
                                      false);
  const std::vector<char> bytes = readBytes(good);
  const std::string cut = (dir_ / "cut.vdb").string();
  int rejected = 0, tried = 0;
  for (size_t keep = 0; keep < bytes.size(); keep += 997) {
    writeBytes(cut, std::vector<char>(bytes.begin(), bytes.begin() + std::ptrdiff_t(keep)));
    ++tried;
    try {
      checkVdbFileStructure(cut, kGridNames);
    } catch (const Error& e) {
      ++rejected;
      EXPECT_NE(std::string(e.what()).find(cut), std::string::npos) << e.what();
    }
  }
  EXPECT_GT(tried, 20);
  EXPECT_EQ(rejected, tried);
}

// A blosc chunk whose stated compressed size is near 2^47: libopenvdb would `new[]` that much.
TEST_F(VdbFileCheck, RejectsAHugeStatedChunkSize) {
  const std::string good = writeGrids(dir_, "good.vdb", openvdb::io::COMPRESS_BLOSC, false);
  std::vector<char> bytes = readBytes(good);
  // The last leaf's chunk: blosc-compressed values end the file, and their int64 size sits
  // before them. Find it by trying every position from the end for a plausible size prefix.
  size_t patched = 0;
  for (size_t pos = bytes.size() - 16; pos > bytes.size() - 4096 && patched == 0; --pos) {
    int64_t stated;
    std::memcpy(&stated, &bytes[pos], 8);
    if (stated > 16 && pos + 8 + size_t(stated) == bytes.size()) patched = pos;
  }
  ASSERT_NE(patched, 0u) << "no blosc chunk size found at the end of the file";
  const int64_t huge = int64_t(1) << 47;
  std::memcpy(&bytes[patched], &huge, 8);
  const std::string bad = (dir_ / "bad.vdb").string();
  writeBytes(bad, bytes);
  try {
    checkVdbFileStructure(bad, kGridNames);
    FAIL() << "accepted a chunk of 2^47 bytes";
  } catch (const Error& e) {
    EXPECT_NE(std::string(e.what()).find("compressed node values needs 140737488355328 bytes"), std::string::npos)
        << e.what();
  }
}

// The inputs tests/fuzz found: readScene must refuse them with vf::Error before libopenvdb
// allocates (under AddressSanitizer such an allocation aborts the process).
TEST_F(VdbFileCheck, RejectsTheFuzzFindings) {
  const fs::path regressions = fs::path(VDBFUSE_SOURCE_DIR) / "tests/fuzz/regressions/scene";
  int files = 0;
  for (const auto& entry : fs::directory_iterator(regressions)) {
    if (entry.path().filename() == "README.md") continue;
    ++files;
    EXPECT_THROW(readScene(entry.path().string()), Error) << entry.path();
  }
  EXPECT_GE(files, 2);
}

TEST_F(VdbFileCheck, RejectsAForeignFileByName) {
  const std::string path = (dir_ / "notes.vdb").string();
  writeBytes(path, std::vector<char>(100, 'x'));
  try {
    checkVdbFileStructure(path, kGridNames);
    FAIL();
  } catch (const Error& e) {
    EXPECT_NE(std::string(e.what()).find(path + ": damaged or unsupported .vdb file (byte 8): not an OpenVDB file"),
              std::string::npos)
        << e.what();
  }
}

}  // namespace
}  // namespace vf

namespace vf {
namespace {

// readSceneHeader (`vdbfuse info`) takes counts from the statistics libopenvdb writes beside
// each grid. A file written without them (File::setGridStatsMetadataEnabled(false)) still
// gives its metadata, and says that its voxels must be read for the counts.
TEST(SceneHeaderStatistics, AFileWithoutGridStatisticsSaysSo) {
  ensureOpenVdbInitialized();
  const fs::path dir = test::tempDir("scene_header_no_stats");
  Scene scene;
  scene.grids().tsdf = openvdb::FloatGrid::create(0.04f);
  scene.grids().tsdf->setName("tsdf");
  scene.grids().tsdf->setGridClass(openvdb::GRID_LEVEL_SET);
  scene.grids().tsdf->setTransform(openvdb::math::Transform::createLinearTransform(0.01));
  scene.grids().tsdf->fill(openvdb::CoordBBox({0, 0, 0}, {15, 15, 15}), 0.01f, true);
  scene.grids().weight = scene.grids().tsdf->deepCopy();
  scene.grids().weight->setName("weight");
  scene.grids().weight->setGridClass(openvdb::GRID_UNKNOWN);
  scene.meta.voxel_size_m = 0.01f;
  scene.meta.truncation_m = 0.04f;
  scene.meta.source = "written without statistics";
  const std::string with = (dir / "with.vdb").string(), without = (dir / "without.vdb").string();
  writeScene(scene, with);
  {
    openvdb::io::File in(with);
    in.open(false);
    openvdb::GridPtrVecPtr grids = in.getGrids();
    openvdb::MetaMap::Ptr meta = in.getMetadata();
    in.close();
    for (auto& g : *grids)
      for (const char* key : {openvdb::GridBase::META_FILE_VOXEL_COUNT, openvdb::GridBase::META_FILE_MEM_BYTES,
                              openvdb::GridBase::META_FILE_BBOX_MIN, openvdb::GridBase::META_FILE_BBOX_MAX})
        g->removeMeta(key);
    openvdb::io::File out(without);
    out.setGridStatsMetadataEnabled(false);
    out.write(*grids, *meta);
    out.close();
  }
  const SceneHeader h = readSceneHeader(with), bare = readSceneHeader(without);
  EXPECT_TRUE(h.statistics_recorded);
  EXPECT_EQ(h.summary.active_voxels, 16u * 16u * 16u);
  EXPECT_FALSE(bare.statistics_recorded);
  EXPECT_EQ(bare.meta.source, "written without statistics");
  EXPECT_FLOAT_EQ(bare.meta.truncation_m, 0.04f);
  EXPECT_EQ(readScene(without).activeVoxelCount(), 16u * 16u * 16u) << "the file itself is fine";
}

}  // namespace
}  // namespace vf
