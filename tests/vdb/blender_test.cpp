// `vdbfuse export --blender` end to end, and in Blender (headless, when installed: Debian's
// blender package, scripts/install-deps.sh): the import script's scene, judged by
// samples/blender/judge_scene.py the way a user would look at it (upright, coloured, framed,
// one camera and one light, a volume that shows), on the shared captures.
#include <gtest/gtest.h>

#include <nlohmann/json.hpp>

#include <array>
#include <cmath>
#include <cstdio>
#include <cstdlib>
#include <filesystem>
#include <map>
#include <string>

#include "io/class_table_io.h"
#include "io/labeled_source.h"
#include "io/mesh_io.h"
#include "io/record3d.h"
#include "io/trajectory_io.h"
#include "io/tum_dataset.h"
#include "synthetic_scene.h"
#include "test_data.h"
#include "vdb/mesher.h"
#include "vdb/scene.h"
#include "vdb/scene_frame.h"

namespace vf {
namespace {

namespace fs = std::filesystem;

std::string run(const std::string& command, int& status) { return test::runCommand(command, status); }

bool haveBlender() {
  int status = 0;
  run("command -v blender", status);
  return status == 0;
}

const std::string kScripts = std::string(VDBFUSE_SOURCE_DIR) + "/samples/blender/";
const std::string kVdbfuse = VDBFUSE_EXE;
// Small, quick pictures: the judge needs coverage and brightness, not detail.
const std::string kJudgeRender = " --judge-resolution 160x90 --judge-samples 8";

// The judge's JSON line from a Blender run's output.
nlohmann::json judged(const std::string& out) {
  const std::string tag = "vdbfuse-judge: ";
  const size_t at = out.rfind(tag);
  if (at == std::string::npos) {
    ADD_FAILURE() << "no judge line in\n" << out;
    return nlohmann::json::object();
  }
  return nlohmann::json::parse(out.substr(at + tag.size(), out.find('\n', at) - at - tag.size()));
}

// Imports `target` (an export folder or one mesh file) with import_scene.py and judges the scene
// in the same Blender run.
nlohmann::json importAndJudge(const std::string& target, const std::string& png) {
  int status = 0;
  const std::string out = run("blender -b --factory-startup --python " + kScripts + "import_scene.py --python " +
                                  kScripts + "judge_scene.py -- " + target + " --judge-render " + png + kJudgeRender,
                              status);
  EXPECT_EQ(status, 0) << out;
  return judged(out);
}

std::string exportSphere(const std::string& name, TriangleMesh* full) {
  test::SyntheticVolume volume(test::sphereSpec(), true);
  test::fillSdf(volume, test::sphereSdf({0, 0, 0}, 0.2f), 0.f);
  SceneMetadata meta;
  meta.classes.classes = {{test::kClassLeft, "chair", {255, 0, 0, 255}}, {test::kClassRight, "dining table", {0, 0, 255, 255}}};
  const Scene scene = sceneFromBricks(volume.view(), meta);
  *full = meshScene(scene);
  const std::string dir = test::tempDir(name);
  writeScene(scene, dir + "/scene.vdb");
  int status = 0;
  const std::string out = run(std::string(VDBFUSE_EXE) + " export " + dir + "/scene.vdb --blender -o " + dir + "/blend", status);
  EXPECT_EQ(status, 0) << out;
  return dir + "/blend";
}

TEST(BlenderExport, FolderHoldsPerClassMeshesVolumeAndManifest) {
  TriangleMesh full;
  const std::string dir = exportSphere("blender_export", &full);
  ASSERT_TRUE(fs::exists(dir + "/chair.ply"));
  ASSERT_TRUE(fs::exists(dir + "/dining_table.ply"));
  ASSERT_TRUE(fs::exists(dir + "/volume.vdb"));
  ASSERT_TRUE(fs::exists(dir + "/scene.json"));
  const TriangleMesh a = readPly(dir + "/chair.ply"), b = readPly(dir + "/dining_table.ply");
  EXPECT_EQ(a.triangleCount() + b.triangleCount(), full.triangleCount());
  EXPECT_TRUE(a.hasColors());
  EXPECT_GT(a.triangleCount(), 1000u);
}

TEST(BlenderExport, ImportScriptLoadsTheFolder) {
  if (!haveBlender()) GTEST_SKIP() << "blender is not installed: the import script was not run";
  int status = 0;
  TriangleMesh full;
  const std::string dir = exportSphere("blender_import", &full);
  const std::string out = run("blender -b --factory-startup --python " + std::string(VDBFUSE_SOURCE_DIR) +
                                  "/samples/blender/import_scene.py -- " + dir + " --save " + dir + "/scene.blend",
                              status);
  EXPECT_EQ(status, 0) << out;
  EXPECT_NE(out.find("vdbfuse: imported 2 meshes and 1 volume(s)"), std::string::npos) << out;
  // Blender holds exactly the exported vertices and faces, and both grids of the volume.
  const std::pair<std::string, std::string> objects[] = {{"chair", "chair"}, {"dining table", "dining_table"}};
  for (const auto& [object, file] : objects) {
    const TriangleMesh exported = readPly(dir + "/" + file + ".ply");
    const std::string line = "vdbfuse: mesh " + object + " vertices " +
                             std::to_string(exported.vertexCount()) + " faces " +
                             std::to_string(exported.triangleCount());
    EXPECT_NE(out.find(line), std::string::npos) << "expected '" << line << "' in\n" << out;
  }
  EXPECT_NE(out.find("vdbfuse: volume grids color,density"), std::string::npos) << out;
  // Nothing of Blender's start-up scene: the meshes, the volume, one camera, one light.
  EXPECT_NE(out.find("vdbfuse: scene objects CAMERA=1 LIGHT=1 MESH=2 VOLUME=1"), std::string::npos) << out;
  EXPECT_TRUE(fs::exists(dir + "/scene.blend")) << out;
}

// Every mesh format the exporter writes arrives in Blender with its faces (Blender merges the
// vertices an OBJ/GLB writer repeats at class seams, so vertices may only shrink there).
TEST(BlenderExport, PlyObjAndGlbImportWithTheirFaces) {
  if (!haveBlender()) GTEST_SKIP() << "blender is not installed: the imports were not run";
  int status = 0;
  TriangleMesh full;
  const std::string dir = exportSphere("blender_formats", &full);
  ClassTable classes;
  classes.classes = {{test::kClassLeft, "chair", {255, 0, 0, 255}}, {test::kClassRight, "dining table", {0, 0, 255, 255}}};
  MeshWriteOptions options;
  options.classes = &classes;
  for (const std::string ext : {"ply", "obj", "glb"}) {
    const std::string path = dir + "/full." + ext;
    writeMesh(full, path, options);
    const std::string out = run("blender -b --factory-startup --python " + std::string(VDBFUSE_SOURCE_DIR) +
                                    "/samples/blender/count_import.py -- " + path, status);
    EXPECT_EQ(status, 0) << out;
    unsigned objects = 0, vertices = 0, faces = 0;
    const size_t at = out.find("vdbfuse: imported ");
    ASSERT_NE(at, std::string::npos) << ext << ":\n" << out;
    ASSERT_EQ(std::sscanf(out.c_str() + at, "vdbfuse: imported %u objects %u vertices %u faces", &objects, &vertices, &faces), 3);
    EXPECT_EQ(faces, full.triangleCount()) << ext;
    EXPECT_GE(objects, 1u) << ext;
    if (ext == "ply") EXPECT_EQ(vertices, full.vertexCount());
    else EXPECT_LE(vertices, full.vertexCount() * 11 / 10) << ext;
  }
}

// ---- the shared captures, as a user would open them ----

// The dance capture (person masked out of the geometry), fused once for the tests below:
// 40 frames at 2 cm, a few seconds on two cores.
class DanceInBlender : public ::testing::Test {
 protected:
  static void SetUpTestSuite() {
    dir_ = test::tempDir("blender_dance");
    const std::string data = test::dataPath("");
    int status = 0;
    fuse_log_ = run(kVdbfuse + " reconstruct " + data + "record3d_dance_head200.r3d --labels " + data +
                        "record3d_dance_head200_labels --dynamic-classes person --max-frames " +
                        std::to_string(kFrames) + " --voxel-size-m 0.02 --device cpu -q -o " +
                        dir_ + "/scene.vdb",
                    status);
    fused_ = status == 0;
  }
  void SetUp() override {
    VF_REQUIRE_DATA(capture, "record3d_dance_head200.r3d");
    ASSERT_TRUE(fused_) << fuse_log_;
    if (!haveBlender()) GTEST_SKIP() << "blender is not installed: the Blender checks were not run";
  }
  static constexpr int kFrames = 40;
  static std::string dir_, fuse_log_;
  static bool fused_;
};
std::string DanceInBlender::dir_, DanceInBlender::fuse_log_;
bool DanceInBlender::fused_ = false;

// Mean sRGB colour of what fusion took from the frames: pixels with depth, not the dancer.
// (The fixture's SetUp has required the capture.)
std::array<double, 3> fusedFramesMeanColor(int frames) {
  const std::string capture = test::dataPath("record3d_dance_head200.r3d");
  const std::string labels = test::dataPath("record3d_dance_head200_labels");
  const LabeledFrameSource source(std::make_unique<Record3dCapture>(capture), labels,
                                  readClassTable(labels + "/classes.json"), MissingLabels::Error);
  std::array<double, 3> sum{0, 0, 0};
  double n = 0;
  for (int i = 0; i < frames; ++i) {
    const RgbdFrame f = source.load(i);
    for (int y = 0; y < f.depth.height(); ++y)
      for (int x = 0; x < f.depth.width(); ++x) {
        if (!(f.depth(x, y) > 0) || f.labels(x, y) != 0) continue;
        // Colour is the phone's 720x960 over 192x256 depth: the pixel fusion samples there.
        const Rgb8 c = f.color((2 * x + 1) * f.color.width() / (2 * f.depth.width()),
                               (2 * y + 1) * f.color.height() / (2 * f.depth.height()));
        sum[0] += c.r, sum[1] += c.g, sum[2] += c.b, n += 1;
      }
  }
  return {sum[0] / n, sum[1] / n, sum[2] / n};
}

TEST_F(DanceInBlender, SavedBlendIsUprightColouredFramedAndItsVolumeShows) {
  int status = 0;
  std::string out = run(kVdbfuse + " export " + dir_ + "/scene.vdb --blender -o " + dir_ + "/blend", status);
  ASSERT_EQ(status, 0) << out;
  EXPECT_NE(out.find("up from recorded poses"), std::string::npos) << "ARKit's gravity is used\n" << out;
  out = run("blender -b --factory-startup --python " + kScripts + "import_scene.py -- " + dir_ + "/blend --save " +
                dir_ + "/dance.blend",
            status);
  ASSERT_EQ(status, 0) << out;
  // The saved file itself, opened again as a user would.
  out = run("blender -b " + dir_ + "/dance.blend --python " + kScripts + "judge_scene.py -- --judge-render " + dir_ +
                "/dance.png --judge-volume-render " + dir_ + "/dance_volume.png" + kJudgeRender,
            status);
  ASSERT_EQ(status, 0) << out;
  const nlohmann::json j = judged(out);
  std::printf("judge: %s\n", j.dump().c_str());
  const auto& objects = j["objects"];
  EXPECT_EQ(objects.value("CAMERA", 0), 1) << objects;
  EXPECT_EQ(objects.value("LIGHT", 0), 1) << objects;
  EXPECT_EQ(objects.value("VOLUME", 0), 1) << objects;
  for (const auto& name : objects["names"]) EXPECT_NE(name.get<std::string>(), "Cube") << "Blender's default cube";
  // Upright: the floor faces +Z.
  EXPECT_LT(j["floor"]["angle_deg"].get<double>(), 25.0) << j["floor"];
  EXPECT_GT(j["floor"]["share"].get<double>(), 0.05) << "a floor holds a good part of the surface";
  // The colours are the frames' (sRGB bytes kept as such through PLY into Blender).
  const std::array<double, 3> frames = fusedFramesMeanColor(kFrames);
  std::printf("frames' mean colour (fused pixels): %.1f %.1f %.1f\n", frames[0], frames[1], frames[2]);
  for (int c = 0; c < 3; ++c) EXPECT_NEAR(j["vertex_color"][c].get<double>(), frames[c], 10.0) << "channel " << c;
  // Framed: the scene fills a good part of the picture, lit neither black nor white.
  EXPECT_GT(j["render"]["coverage"].get<double>(), 0.2) << j["render"];
  EXPECT_GT(j["render"]["mean_luma"].get<double>(), 60.0) << j["render"];
  EXPECT_LT(j["render"]["mean_luma"].get<double>(), 200.0) << j["render"];
  // The volume alone covers about what the meshes do.
  EXPECT_GT(j["volume_render"]["coverage"].get<double>(), 0.5 * j["render"]["coverage"].get<double>())
      << j["volume_render"];
  EXPECT_GT(j["volume_render"]["mean_luma"].get<double>(), 20.0) << j["volume_render"];
}

// GLB (Y-up, linear COLOR_0, white base colour), OBJ (Y-up, -Z forward, sRGB vertex colours)
// and PLY (Z-up, sRGB bytes) of one scene: the same picture in Blender, upright each time.
TEST_F(DanceInBlender, GlbObjAndPlyRenderAlike) {
  std::map<std::string, double> luma;
  for (const std::string ext : {"ply", "obj", "glb"}) {
    const std::string mesh = dir_ + "/dance." + ext;
    int status = 0;
    const std::string out = run(kVdbfuse + " mesh " + dir_ + "/scene.vdb -o " + mesh, status);
    ASSERT_EQ(status, 0) << out;
    const nlohmann::json j = importAndJudge(mesh, dir_ + "/dance_" + ext + ".png");
    std::printf("%s: %s\n", ext.c_str(), j.dump().c_str());
    EXPECT_LT(j["floor"]["angle_deg"].get<double>(), 25.0) << ext << ": " << j["floor"];
    EXPECT_GT(j["render"]["coverage"].get<double>(), 0.2) << ext;
    luma[ext] = j["render"]["mean_luma"].get<double>();
  }
  for (const auto& [ext, value] : luma) {
    EXPECT_NEAR(value, luma["ply"], 0.1 * luma["ply"]) << ext << " against ply";
  }
}

// A TUM scene tracked by ICP alone stands upright: up from the floor plane, checked against the
// motion capture's z (TUM's world is z-up) and in Blender.
TEST(TumInBlender, IcpSceneIsUpright) {
  VF_REQUIRE_DATA(folder, "tum_fr1_xyz_head100");
  const std::string dir = test::tempDir("blender_tum");
  int status = 0;
  std::string out = run(kVdbfuse + " reconstruct " + folder + " --poses icp --max-frames 20 "
                            "--voxel-size-m 0.02 --device cpu -q -o " + dir + "/scene.vdb",
                        status);
  ASSERT_EQ(status, 0) << out;
  EXPECT_NE(out.find("up: floor plane"), std::string::npos) << out;
  const Scene scene = readScene(dir + "/scene.vdb");
  const Trajectory fused = readTumTrajectory(dir + "/scene.txt");
  const TumDataset tum(folder);
  ASSERT_TRUE(tum.load(0).T_world_cam_given.has_value());
  const Vec3f gravity_up = recordedUpInFusedFrame({0, 0, 1}, *tum.load(0).T_world_cam_given, fused[0].T_world_cam);
  const Vec3f in_file = exportRotation(scene.meta, SceneAxes::kZUp).rotate(gravity_up);
  const double tilt = std::acos(std::clamp(double(in_file.z), -1.0, 1.0)) * 180 / M_PI;
  std::printf("TUM fr1/xyz, ICP: the motion capture's up is %.1f degrees from the export's +Z\n", tilt);
  EXPECT_LT(tilt, 25.0);
  if (!haveBlender()) GTEST_SKIP() << "blender is not installed: the Blender check was not run";
  out = run(kVdbfuse + " mesh " + dir + "/scene.vdb -o " + dir + "/tum.ply", status);
  ASSERT_EQ(status, 0) << out;
  const nlohmann::json j = importAndJudge(dir + "/tum.ply", dir + "/tum.png");
  std::printf("judge: %s\n", j.dump().c_str());
  EXPECT_LT(j["floor"]["angle_deg"].get<double>(), 25.0) << j["floor"];
}

}  // namespace
}  // namespace vf
