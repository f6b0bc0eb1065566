// `vdbfuse reconstruct --labels ...` end to end on the first frames of the Record3D capture:
// the class table lands in the .vdb, class names resolve, and missing maps are skipped or fatal.
#include <gtest/gtest.h>

#include <cstdio>
#include <filesystem>

#include "io/image_io.h"
#include "test_data.h"
#include "vdb/scene.h"

namespace vf {
namespace {

namespace fs = std::filesystem;

std::string run(const std::string& command, int& status) { return test::runCommand(command, status); }

const std::string kSmallVolume = " --voxel-size-m 0.02 -q -f";

TEST(ReconstructLabels, PersonMasksGiveAClassGridAndTheTableInTheScene) {
  VF_REQUIRE_DATA(capture, "record3d_dance_head200.r3d");
  VF_REQUIRE_DATA(labels, "record3d_dance_head200_labels");
  const std::string out = test::tempDir("cli_labels") + "/scene.vdb";
  int status = 0;
  const std::string log = run(std::string(VDBFUSE_EXE) + " reconstruct " + capture + " --labels " + labels +
                                  " --dynamic-classes person --poses given --max-frames 4 -o " + out + kSmallVolume,
                              status);
  ASSERT_EQ(status, 0) << log;
  EXPECT_NE(log.find("labels: 4 of 4 frames labelled"), std::string::npos) << log;
  const Scene scene = readScene(out);
  EXPECT_TRUE(scene.hasClasses());
  ASSERT_NE(scene.meta.classes.findName("person"), nullptr);
  EXPECT_EQ(scene.meta.classes.findName("person")->id, 1);
  EXPECT_GT(scene.activeVoxelCount(), 50000u);
}

TEST(ReconstructLabels, UnknownDynamicClassListsTheValidNames) {
  VF_REQUIRE_DATA(capture, "record3d_dance_head200.r3d");
  VF_REQUIRE_DATA(labels, "record3d_dance_head200_labels");
  int status = 0;
  const std::string log = run(std::string(VDBFUSE_EXE) + " reconstruct " + capture + " --labels " + labels +
                                  " --dynamic-classes dancer --max-frames 2 -o " + test::tempDir("cli_bad") +
                                  "/s.vdb" + kSmallVolume,
                              status);
  EXPECT_NE(status, 0);
  EXPECT_NE(log.find("unknown class 'dancer'"), std::string::npos) << log;
  EXPECT_NE(log.find("background (0), person (1)"), std::string::npos) << log;
}

TEST(ReconstructLabels, MissingClassTableAndMissingMapsAreReported) {
  VF_REQUIRE_DATA(capture, "record3d_dance_head200.r3d");
  // Maps for frames 0 and 1 only, at depth resolution (192x256), no classes.json.
  const std::string dir = test::tempDir("cli_missing");
  const std::string maps = dir + "/maps";
  fs::create_directories(maps);
  LabelImage zeros(192, 256);
  for (int i = 0; i < 192 * 256; ++i) zeros.data()[i] = 0;
  writeLabelPng(maps + "/0.png", zeros);
  writeLabelPng(maps + "/1.png", zeros);
  const std::string base = std::string(VDBFUSE_EXE) + " reconstruct " + capture + " --labels " + maps +
                           " --poses given --max-frames 3 -o " + dir + "/s.vdb" + kSmallVolume;
  int status = 0;
  std::string log = run(base, status);
  EXPECT_NE(status, 0);
  EXPECT_NE(log.find("--classes"), std::string::npos) << log;

  const std::string table = std::string(VDBFUSE_SOURCE_DIR) + "/samples/classes/person.json";
  log = run(base + " --classes " + table + " --labels-missing error", status);
  EXPECT_NE(status, 0);
  EXPECT_NE(log.find(maps + "/2.png"), std::string::npos) << log;

  log = run(base + " --classes " + table, status);  // skip is the default
  ASSERT_EQ(status, 0) << log;
  EXPECT_NE(log.find("labels: 2 of 3 frames labelled; 1 without a label map"), std::string::npos) << log;
  EXPECT_NE(log.find(maps + "/2.png"), std::string::npos) << log;
}

}  // namespace
}  // namespace vf
