// Issue 37: `vdbfuse info` answers from the file's headers. A scene whose voxel data is damaged
// still gets its counts (the trees are not read); the peak memory does not grow with the scene;
// --extent reads the voxels and says what only they tell.
#include <gtest/gtest.h>
#include <sys/resource.h>
#include <sys/wait.h>
#include <unistd.h>

#include <filesystem>
#include <fstream>
#include <string>
#include <vector>

#include "reliability/cli_harness.h"
#include "reliability/scene_fixture.h"
#include "test_data.h"
#include "vdb/scene.h"
#include "vdb/scene_info.h"

namespace vf {
namespace {

namespace fs = std::filesystem;
using test::CliRun;
using test::runVdbfuse;

// Peak resident memory (MB) of `vdbfuse args`, its output discarded; -1 if it failed. Linux
// starts a child's peak at the size of the process it was forked from, so this test keeps
// itself small (the scenes are written by forked children, writeFixtureApart).
double peakMegabytes(const std::vector<std::string>& args) {
  const pid_t pid = fork();
  if (pid == 0) test::execVdbfuse(args, 0, open("/dev/null", O_WRONLY));
  int raw = 0;
  rusage usage{};
  if (wait4(pid, &raw, 0, &usage) != pid || test::statusOf(raw) != 0) return -1;
  return usage.ru_maxrss / 1024.0;  // Linux: kilobytes
}

// test::writeSceneFixture in a child process, whose memory goes with it.
std::string writeFixtureApart(const std::string& dir, int dims) {
  const pid_t pid = fork();
  if (pid == 0) {
    test::writeSceneFixture(dir, dims, 0.01f);
    _exit(0);
  }
  int raw = 0;
  waitpid(pid, &raw, 0);
  EXPECT_EQ(test::statusOf(raw), 0);
  return dir + "/scene.vdb";
}

TEST(InfoHeaders, PrintsTheHeadersCountsAndExtentOnRequest) {
  const std::string dir = test::tempDir("info_headers");
  const std::string path = test::writeSceneFixture(dir);
  const size_t active = summarizeScene(readScene(path)).active_voxels;
  const CliRun fast = runVdbfuse({"info", path});
  ASSERT_EQ(fast.status, 0) << fast.output;
  EXPECT_NE(fast.output.find("active       " + std::to_string(active) + " voxels\n"), std::string::npos) << fast.output;
  EXPECT_NE(fast.output.find("classes (2 in table; info --extent counts"), std::string::npos) << fast.output;
  EXPECT_NE(fast.output.find("a/b"), std::string::npos) << fast.output;
  EXPECT_NE(fast.output.find("bounds       ["), std::string::npos) << fast.output;
  const CliRun full = runVdbfuse({"info", "--extent", path});
  ASSERT_EQ(full.status, 0) << full.output;
  EXPECT_NE(full.output.find("active       " + std::to_string(active) + " voxels ("), std::string::npos) << full.output;
  EXPECT_NE(full.output.find(" on the surface)"), std::string::npos) << full.output;
  // Everything the fast answer prints before the grids' table, but the counts, is the same.
  const auto line = [](const std::string& text, const std::string& key) {
    const size_t at = text.find(key);
    return at == std::string::npos ? std::string() : text.substr(at, text.find('\n', at) - at);
  };
  for (const char* key : {"source ", "voxel ", "bounds ", "grids\n  tsdf"})
    EXPECT_EQ(line(fast.output, key), line(full.output, key)) << key;
}

TEST(InfoHeaders, DamagedVoxelDataDoesNotStopInfoButStopsExtent) {
  const std::string dir = test::tempDir("info_headers_damaged");
  const std::string path = test::writeSceneFixture(dir);
  const uintmax_t size = fs::file_size(path);
  {
    std::fstream f(path, std::ios::in | std::ios::out | std::ios::binary);
    const std::string garbage(2048, '\xA5');
    f.seekp(std::streamoff(size - garbage.size() - 64));  // the last grid's leaf values
    f.write(garbage.data(), std::streamsize(garbage.size()));
  }
  const CliRun fast = runVdbfuse({"info", path});
  EXPECT_EQ(fast.status, 0) << "the trees are not read, so their damage is not seen:\n" << fast.output;
  EXPECT_NE(fast.output.find(" voxels\n"), std::string::npos) << fast.output;
  const CliRun full = runVdbfuse({"info", "--extent", path});
  EXPECT_NE(full.status, 0) << full.output;
  EXPECT_NE(full.output.find(path), std::string::npos) << full.output;
}

// A scene of 1.8 M active voxels (over 100 MB of grids in memory) against one of 60 k: the
// header answer's peak memory stays the same, reading the voxels does not.
TEST(InfoHeaders, PeakMemoryDoesNotGrowWithTheScene) {
  const std::string small_dir = test::tempDir("info_headers_small"), large_dir = test::tempDir("info_headers_large");
  const std::string small = writeFixtureApart(small_dir, 48), large = writeFixtureApart(large_dir, 448);
  ASSERT_GT(readSceneHeader(large).summary.active_voxels, 1500000u);
  const double small_mb = peakMegabytes({"info", small}), large_mb = peakMegabytes({"info", large});
  const double extent_mb = peakMegabytes({"info", "--extent", large});
  ASSERT_GT(small_mb, 0);
  ASSERT_GT(large_mb, 0);
  ASSERT_GT(extent_mb, 0);
  std::printf("peak memory of info: %.1f MB (small scene), %.1f MB (large), --extent %.1f MB (large)\n", small_mb,
              large_mb, extent_mb);
  EXPECT_LT(large_mb - small_mb, 8.0) << "the header answer must not read the grids";
  EXPECT_GT(extent_mb - large_mb, 60.0) << "the test scene is too small to show the difference";
  EXPECT_LT(large_mb, 100.0);
}

}  // namespace
}  // namespace vf
