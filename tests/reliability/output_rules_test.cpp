// The README's output rules, the same for every command: an existing output is kept unless
// --force is given, no output replaces an input or another output, an output's name says its
// format, and per-class files never replace one another. Invalid option values are refused with
// the option named, never replaced by a default.
#include <gtest/gtest.h>

#include <filesystem>

#include "io/zip_archive.h"
#include "reliability/cli_harness.h"
#include "reliability/scene_fixture.h"
#include "test_data.h"

namespace vf {
namespace {

namespace fs = std::filesystem;
using test::runVdbfuse;

class OutputRulesTest : public ::testing::Test {
 protected:
  void SetUp() override {
    dir_ = test::tempDir(std::string("output_rules_") +
                         ::testing::UnitTest::GetInstance()->current_test_info()->name());
    scene_ = test::writeSceneFixture(dir_);
  }
  // The run fails with status 1 (an error, not a crash), says `expected`, and changes no file.
  void expectRefused(const std::vector<std::string>& args, const std::string& expected) {
    SCOPED_TRACE(args[0] + " ... " + expected);
    const auto before = test::snapshot(dir_);
    const test::CliRun run = runVdbfuse(args);
    EXPECT_EQ(run.status, 1) << run.output;
    EXPECT_NE(run.output.find(expected), std::string::npos) << run.output;
    EXPECT_EQ(run.output.find("internal error"), std::string::npos) << run.output;
    EXPECT_EQ(test::changedFiles(before, test::snapshot(dir_)), std::vector<std::string>{});
    EXPECT_EQ(test::temporariesUnder(dir_), std::vector<std::string>{});
  }
  std::string dir_, scene_;
};

TEST_F(OutputRulesTest, ExistingOutputsAreKeptWithoutForce) {
  const std::string old = "keep me\n";
  for (const std::string name : {"mesh.ply", "mesh.obj", "points.ply"}) test::writeText(dir_ + "/" + name, old);
  expectRefused({"mesh", scene_, "-o", dir_ + "/mesh.ply"}, "--force");
  expectRefused({"mesh", scene_, "-o", dir_ + "/mesh.obj"}, "--force");
  expectRefused({"export", scene_, "--points", "-o", dir_ + "/points.ply"}, "--force");
  fs::create_directory(dir_ + "/blender");
  test::writeText(dir_ + "/blender/mine.txt", old);
  expectRefused({"export", scene_, "--blender", "-o", dir_ + "/blender"}, "--force");
  // The .mtl beside an OBJ is an output too.
  test::writeText(dir_ + "/other.mtl", old);
  expectRefused({"mesh", scene_, "-o", dir_ + "/other.obj"}, "other.mtl");
  // With --force they are replaced.
  EXPECT_EQ(runVdbfuse({"mesh", scene_, "-o", dir_ + "/mesh.ply", "--force"}).status, 0);
  EXPECT_NE(test::fileContent(dir_ + "/mesh.ply"), old);
  const test::CliRun blender = runVdbfuse({"export", scene_, "--blender", "-o", dir_ + "/blender", "--force"});
  EXPECT_EQ(blender.status, 0) << blender.output;
  EXPECT_TRUE(fs::exists(dir_ + "/blender/volume.vdb"));
  EXPECT_FALSE(fs::exists(dir_ + "/blender/mine.txt"));
}

TEST_F(OutputRulesTest, ScreenshotKeepsAnExistingPicture) {
  const std::string viewer = fs::path(test::vdbfuseExe()).parent_path().string() + "/vdbfuse-view";
  if (!fs::exists(viewer)) GTEST_SKIP() << "built without the viewer (-DVDBFUSE_WITH_VIEWER=OFF)";
  test::writeText(dir_ + "/shot.png", "keep me\n");
  // Refused before a display is needed.
  expectRefused({"view", scene_, "--screenshot", dir_ + "/shot.png"}, "--force");
  expectRefused({"view", scene_, "--screenshot", scene_, "--force"}, "--screenshot");
}

TEST_F(OutputRulesTest, AnOutputIsNeverAnInputOrAnotherOutput) {
  // The Blender folder holding the scene it is made from.
  fs::create_directory(dir_ + "/d");
  const std::string inner = dir_ + "/d/volume.vdb";
  fs::copy_file(scene_, inner);
  expectRefused({"export", inner, "--blender", "-o", dir_ + "/d", "--force"}, "input");
  expectRefused({"export", inner, "--blender", "-o", dir_ + "/d/../d/", "--force"}, "input");
  expectRefused({"edit", scene_, "-o", dir_ + "/./scene.vdb", "--force"}, "input");
  // The trajectory copied beside an edit's output must not be the scene's own.
  VF_REQUIRE_DATA(dataset, "tum_fr3_teddy_head60");
  expectRefused({"reconstruct", dataset, "-o", dir_ + "/x.vdb", "--trajectory", dir_ + "/x.vdb", "--max-frames", "2"},
                "--trajectory");
  // A file of the input folder: on a folder of this test's own (frames linked, the ground truth
  // copied), so that a binary without the rule (VDBFUSE_EXE) cannot replace the shared data's.
  const std::string own = dir_ + "/dataset";
  fs::create_directories(own);
  for (const std::string name : {"rgb", "depth", "rgb.txt", "depth.txt", "camera_intrinsics.txt"})
    fs::create_symlink(dataset + "/" + name, own + "/" + name);
  fs::copy_file(dataset + "/groundtruth.txt", own + "/groundtruth.txt");
  expectRefused({"reconstruct", own, "-o", dir_ + "/x.vdb", "--trajectory", own + "/groundtruth.txt", "--max-frames",
                 "2", "--force"},
                "input");
}

// An output inside an input folder changes the input (issue 35, cause 3): renders among a
// dataset's files, a scene beside its frames, a converted capture inside the capture's own rgbd/
// folder (read back as frames). Refused for every command, naming both.
TEST_F(OutputRulesTest, AnOutputNeverLandsInsideAnInputFolder) {
  VF_REQUIRE_DATA(dataset, "tum_fr3_teddy_head60");
  VF_REQUIRE_DATA(capture, "record3d_dance_head200.r3d");
  // Folders of this test's own (frames linked), so that a binary without the rule (VDBFUSE_EXE)
  // writes into them, not into the shared data.
  const std::string own = dir_ + "/dataset";
  fs::create_directories(own);
  for (const std::string name : {"rgb", "depth", "rgb.txt", "depth.txt", "camera_intrinsics.txt", "groundtruth.txt"})
    fs::create_symlink(dataset + "/" + name, own + "/" + name);
  const std::vector<std::string> fuse = {"reconstruct", own, "--max-frames", "2", "--device", "cpu", "-q"};
  const auto with = [](std::vector<std::string> args, const std::vector<std::string>& more) {
    args.insert(args.end(), more.begin(), more.end());
    return args;
  };
  expectRefused(with(fuse, {"-o", dir_ + "/x.vdb", "--renders", own + "/renders"}),
                "--renders " + own + "/renders is inside " + own + ", a folder this command reads");
  expectRefused(with(fuse, {"-o", own + "/x.vdb"}), "-o " + own + "/x.vdb is inside " + own);
  expectRefused(with(fuse, {"-o", dir_ + "/x.vdb", "--trajectory", own + "/../dataset/poses.txt"}),
                "--trajectory " + own + "/../dataset/poses.txt is inside " + own);
  // A Record3D capture unzipped into a folder (three frames of it).
  const std::string unzipped = dir_ + "/capture";
  fs::create_directories(unzipped + "/rgbd");
  const ZipArchive zip(capture);
  for (const std::string entry : {"metadata", "rgbd/0.jpg", "rgbd/0.depth", "rgbd/0.conf", "rgbd/1.jpg",
                                  "rgbd/1.depth", "rgbd/1.conf", "rgbd/2.jpg", "rgbd/2.depth", "rgbd/2.conf"}) {
    const std::vector<uint8_t> bytes = zip.read(entry);
    test::writeText(unzipped + "/" + entry, std::string(bytes.begin(), bytes.end()));
  }
  expectRefused({"convert", unzipped, unzipped + "/rgbd/9.depth", "--max-frames", "2"},
                "output " + unzipped + "/rgbd/9.depth is inside " + unzipped + ", a folder this command reads");
  expectRefused({"convert", unzipped, unzipped + "/tum"}, "output " + unzipped + "/tum is inside " + unzipped);
  // Beside the input folder is fine.
  const test::CliRun beside = runVdbfuse({"convert", unzipped, dir_ + "/tum", "--max-frames", "2"});
  EXPECT_EQ(beside.status, 0) << beside.output;
}

TEST_F(OutputRulesTest, AnOutputsNameSaysItsFormat) {
  VF_REQUIRE_DATA(dataset, "tum_fr3_teddy_head60");
  expectRefused({"reconstruct", dataset, "-o", dir_ + "/a.ply", "--max-frames", "2"}, ".vdb");
  expectRefused({"edit", scene_, "-o", dir_ + "/a.ply"}, ".vdb");
  expectRefused({"mesh", scene_, "-o", dir_ + "/a.vdb"}, ".ply");
  expectRefused({"export", scene_, "--points", "-o", dir_ + "/a.obj"}, ".ply");
}

TEST_F(OutputRulesTest, ClassNamesThatSanitiseAlikeGetFilesOfTheirOwn) {
  // "a/b" and "a_b" both become a_b: each class must keep its own mesh.
  const test::CliRun run = runVdbfuse({"mesh", scene_, "-o", dir_ + "/m.ply", "--per-class"});
  ASSERT_EQ(run.status, 0) << run.output;
  std::vector<std::string> meshes;
  for (const auto& e : fs::directory_iterator(dir_))
    if (e.path().extension() == ".ply") meshes.push_back(e.path().filename().string());
  std::sort(meshes.begin(), meshes.end());
  EXPECT_EQ(meshes, (std::vector<std::string>{"m_a_b.ply", "m_a_b_2.ply"})) << run.output;
  EXPECT_NE(test::fileContent(dir_ + "/m_a_b.ply"), test::fileContent(dir_ + "/m_a_b_2.ply"));

  const test::CliRun blender = runVdbfuse({"export", scene_, "--blender", "-o", dir_ + "/blender"});
  ASSERT_EQ(blender.status, 0) << blender.output;
  EXPECT_TRUE(fs::exists(dir_ + "/blender/a_b.ply"));
  EXPECT_TRUE(fs::exists(dir_ + "/blender/a_b_2.ply"));
  EXPECT_NE(test::fileContent(dir_ + "/blender/scene.json").find("a_b_2.ply"), std::string::npos);
}

TEST_F(OutputRulesTest, InvalidValuesAreRefusedNotReplaced) {
  VF_REQUIRE_DATA(dataset, "tum_fr3_teddy_head60");
  const std::vector<std::string> base = {"reconstruct", dataset, "-o", dir_ + "/r.vdb", "--device", "cpu", "-q"};
  const std::vector<std::pair<std::vector<std::string>, std::string>> cases = {
      {{"--voxel-size-m", "0"}, "--voxel-size-m"},   {{"--voxel-size-m", "-1"}, "--voxel-size-m"},
      {{"--voxel-size-m", "nan"}, "--voxel-size-m"}, {{"--voxel-size-m", "1e-9"}, "--voxel-size-m"},
      {{"--truncation-m", "-1"}, "--truncation-m"},  {{"--truncation-m", "1e9"}, "--truncation-m"},
      {{"--max-frames", "0"}, "--max-frames"},       {{"--max-frames", "-1"}, "--max-frames"},
      {{"--intrinsics", "525,525,1e9,239"}, "--intrinsics"},
      {{"--fuse-depth", "smoothed"}, "--fuse-depth smoothed: expected filtered or raw"},
  };
  for (const auto& [extra, option] : cases) {
    SCOPED_TRACE(extra[0] + " " + extra[1]);
    const test::CliRun run = runVdbfuse(test::withArgs(base, extra), 0, 120);
    EXPECT_NE(run.status, 0) << run.output;
    EXPECT_LT(run.status, 100 + 28) << "killed or timed out: " << run.output;  // CLI11 uses 100+ for parse errors
    EXPECT_NE(run.output.find(option), std::string::npos) << run.output;
    EXPECT_EQ(run.output.find("internal error"), std::string::npos) << run.output;
    EXPECT_LT(run.cpu_seconds, 30) << "took " << run.cpu_seconds << " s of CPU to refuse";
    EXPECT_FALSE(fs::exists(dir_ + "/r.vdb"));
  }
  for (const std::vector<std::string>& args : {std::vector<std::string>{"mesh", scene_, "-o", dir_ + "/m.ply"},
                                              std::vector<std::string>{"edit", scene_, "-o", dir_ + "/m.vdb",
                                                                       "--remove-outliers"}}) {
    const std::string& command = args[0];
    std::vector<std::string> with = args;
    with.insert(with.end(), {"--min-component", "-1"});
    const test::CliRun run = runVdbfuse(with);
    EXPECT_NE(run.status, 0) << command << ": " << run.output;
    EXPECT_NE(run.output.find("--min-component"), std::string::npos) << command << ": " << run.output;
  }
}

}  // namespace
}  // namespace vf
