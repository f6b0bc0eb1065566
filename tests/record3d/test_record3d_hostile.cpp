// Issue 35's hostile Record3D metadata: sizes that contradict the images, poses that are not
// rotations or not finite, a K that cannot be fused and fields of the wrong JSON type. Each must
// be refused at open, naming the capture and the field (or entry) and what is wrong.
#include <gtest/gtest.h>

#include <functional>
#include <map>

#include "core/error.h"
#include "io/record3d.h"
#include "io/zip_archive.h"
#include "r3d_test_util.h"
#include "test_data.h"

namespace vf {
namespace {

using test::errorOf;

const char* const kK = R"("K":[717.0636596679688,0,0,0,717.0636596679688,0,359.244873046875,485.18304443359375,1])";

// Two frames made of the dance capture's frame 0 (colour 720x960, depth 192x256) under the
// metadata `fields` (JSON object members, without braces).
std::string captureWith(const std::string& name, const std::string& fields) {
  ZipArchive src(test::dataPath("record3d_dance_head200.r3d"));
  std::map<std::string, std::vector<uint8_t>> e;
  e["metadata"] = test::toBytes("{" + fields + "}");
  for (int i = 0; i < 2; ++i)
    for (const char* ext : {".jpg", ".depth", ".conf"})
      e["rgbd/" + std::to_string(i) + ext] = src.read("rgbd/0" + std::string(ext));
  const std::string path = test::tempDir("r3d_hostile_" + name) + "/capture.r3d";
  test::writeZip(path, e);
  return path;
}

std::string openError(const std::string& path) {
  return errorOf([&] {
    Record3dCapture capture(path);
    capture.load(0);
  });
}

bool contains(const std::string& text, const std::string& part) { return text.find(part) != std::string::npos; }

// Cause 10: w x h swapped against the JPEGs gave a 256x192 depth map of the 192x256 data (rows
// read with the wrong stride) and colour stretched from 720x960 to 960x720.
TEST(Record3dHostile, MetadataSizesThatContradictTheImagesAreRefused) {
  VF_REQUIRE_DATA(r3d, "record3d_dance_head200.r3d");
  const std::string swapped = captureWith(
      "swapped", R"("w":960,"h":720,"fps":30,"K":[717,0,0,0,717,0,485,359,1])");
  std::string e = openError(swapped);
  EXPECT_TRUE(contains(e, swapped + ": entry 'rgbd/0.jpg': the colour image is 720x960 but the metadata says w x h = "
                              "960x720")) << e;

  const std::string half = captureWith("half", std::string(R"("w":360,"h":480,"fps":30,)") +
                                                   R"("K":[358,0,0,0,358,0,180,242,1])");
  e = openError(half);
  EXPECT_TRUE(contains(e, "the colour image is 720x960 but the metadata says w x h = 360x480")) << e;

  // dw x dh against w x h: 256x192 holds as many floats as the real 192x256, so the blob's size
  // could not tell.
  const std::string depth = captureWith("depth_size", std::string(R"("w":720,"h":960,"dw":256,"dh":192,"fps":30,)") + kK);
  e = openError(depth);
  EXPECT_TRUE(contains(e, depth + ": metadata: dw x dh = 256x192 and w x h = 720x960 have different aspect "
                              "ratios")) << e;

  // The capture as it is opens.
  EXPECT_EQ(openError(captureWith("fine", std::string(R"("w":720,"h":960,"fps":30,)") + kK)), "(no error)");
}

// Cause 25: "Record3D pose quaternion is not a rotation" named neither the file nor the pose.
TEST(Record3dHostile, BadPosesNameTheCaptureAndThePoseIndex) {
  VF_REQUIRE_DATA(r3d, "record3d_dance_head200.r3d");
  const std::string zero = captureWith("zero_quaternion", std::string(R"("w":720,"h":960,"fps":30,)") + kK +
                                                              R"(,"poses":[[0,0,0,1,0,0,0],[0,0,0,0,0,0,0]])");
  std::string e = openError(zero);
  EXPECT_TRUE(contains(e, zero + ": metadata: 'poses[1]' (the pose of frame 1): quaternion (qx, qy, qz, qw) has "
                             "length 0")) << e;

  const std::string infinite = captureWith("inf_pose", std::string(R"("w":720,"h":960,"fps":30,)") + kK +
                                                           R"(,"poses":[[0,0,0,1,0,0,0],[0,0,0,1,1e999,0,0]])");
  // JSON has no inf or NaN: an overflowing number is refused by the parser, naming the capture.
  e = openError(infinite);
  EXPECT_TRUE(contains(e, infinite + ": metadata: metadata is not valid JSON")) << e;
  EXPECT_TRUE(contains(e, "1e999")) << e;

  const std::string init = captureWith("init_pose", std::string(R"("w":720,"h":960,"fps":30,)") + kK +
                                                        R"(,"initPose":[0,0,0,5,0,0,0])");
  e = openError(init);
  EXPECT_TRUE(contains(e, init + ": metadata: 'initPose' quaternion (qx, qy, qz, qw) has length 5")) << e;
}

// Found beside cause 12: two frames at one time wrote a trajectory `evaluate` refuses.
TEST(Record3dHostile, TwoFramesAtOneTimeAreRefused) {
  VF_REQUIRE_DATA(r3d, "record3d_dance_head200.r3d");
  const std::string path =
      captureWith("same_time", std::string(R"("w":720,"h":960,"frameTimestamps":[10.5,10.5000001],)") + kK);
  const std::string e = openError(path);
  EXPECT_TRUE(contains(e, path + ": metadata: 'frameTimestamps[0]' and 'frameTimestamps[1]' are both 10.500000 s")) << e;
}

// Cause 19: a K the pipeline cannot fuse was reported as "Intrinsics.cx (--intrinsics)".
TEST(Record3dHostile, AnUnusableKNamesTheCaptureAndK) {
  VF_REQUIRE_DATA(r3d, "record3d_dance_head200.r3d");
  const std::string path = captureWith("bad_k", R"("w":720,"h":960,"fps":30,"K":[717,0,0,0,717,0,5000,485,1])");
  const std::string e = openError(path);
  EXPECT_TRUE(contains(e, path + ": metadata: 'K' (for the 720x960 RGB image): cx = 5000 lies outside the "
                             "720-pixel-wide image")) << e;
  EXPECT_FALSE(contains(e, "--intrinsics")) << e;
}

// Cause 26: "[json.exception.type_error.302] type must be number, but is string" named no field.
TEST(Record3dHostile, FieldsOfTheWrongTypeAreNamed) {
  VF_REQUIRE_DATA(r3d, "record3d_dance_head200.r3d");
  struct Case {
    std::string fields, expected;
  };
  const std::vector<Case> cases = {
      {std::string(R"("w":720,"h":960,"fps":"30",)") + kK, "'fps' must be a number, got \"30\" (a string)"},
      {R"("w":720,"h":960,"fps":30,"K":[717,0,0,0,"717",0,359,485,1])", "'K[4]' must be a number, got \"717\""},
      {R"("w":720,"h":960,"fps":30,"K":{"fx":717})", "'K' must be an array, got {\"fx\":717} (an object)"},
      {R"("w":[720],"h":960,"fps":30,"K":[])", "'w' must be a number, got [720] (an array)"},
      {std::string(R"("w":720,"h":960,"frameTimestamps":[0.5,null],)") + kK, "'frameTimestamps[1]' must be a number"},
      {std::string(R"("w":720,"h":960,"fps":30,"poses":[[0,0,0,1,0,0,"x"]],)") + kK, "'poses[0][6]' must be a number"},
  };
  for (size_t i = 0; i < cases.size(); ++i) {
    const std::string path = captureWith("json_" + std::to_string(i), cases[i].fields);
    const std::string e = openError(path);
    EXPECT_TRUE(contains(e, path + ": metadata: " + cases[i].expected)) << e;
    EXPECT_FALSE(contains(e, "json.exception")) << e;
  }
}

}  // namespace
}  // namespace vf
