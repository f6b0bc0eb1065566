// `vdbfuse mesh --texture --target-triangles` and `export --blender --texture` end to end on the
// shared captures, and their import in headless Blender when it is installed (Debian's blender
// package): the glTF add-on run unpatched.
#include <gtest/gtest.h>

#include <cstdio>
#include <cstring>
#include <fstream>
#include <nlohmann/json.hpp>

#include "io/mesh_io.h"
#include "io/mesh_metrics.h"
#include "io/triangle_bvh.h"
#include "test_data.h"

namespace vf {
namespace {

namespace fs = std::filesystem;

const std::string kVdbfuse = VDBFUSE_EXE;
const std::string kScripts = std::string(VDBFUSE_SOURCE_DIR) + "/samples/blender/";

std::string run(const std::string& command, int& status) { return test::runCommand(command, status); }

bool haveBlender() {
  int status = 0;
  run("command -v blender", status);
  return status == 0;
}

// The JSON chunk of a GLB file.
nlohmann::json glbJson(const std::string& path) {
  std::ifstream in(path, std::ios::binary);
  char header[20];
  in.read(header, 20);
  uint32_t length = 0;
  std::memcpy(&length, header + 12, 4);
  std::string text(length, '\0');
  in.read(text.data(), std::streamsize(length));
  return nlohmann::json::parse(text);
}

// The number after `key` in a command's output (the first occurrence), or -1.
double numberAfter(const std::string& out, const std::string& key) {
  const size_t at = out.find(key);
  return at == std::string::npos ? -1 : std::atof(out.c_str() + at + key.size());
}

// The dance capture fused once for the tests below: person masked, phone poses, 2 cm voxels.
class TexturedDance : public ::testing::Test {
 protected:
  static void SetUpTestSuite() {
    dir_ = test::tempDir("textured_dance");
    const std::string data = test::dataPath("");
    int status = 0;
    log_ = run(kVdbfuse + " reconstruct " + data + "record3d_dance_head200.r3d --labels " + data +
                   "record3d_dance_head200_labels --dynamic-classes person --poses given --max-frames 60 "
                   "--voxel-size-m 0.02 --device cpu -q -o " + dir_ + "/scene.vdb",
               status);
    fused_ = status == 0;
  }
  void SetUp() override {
    VF_REQUIRE_DATA(capture, "record3d_dance_head200.r3d");
    ASSERT_TRUE(fused_) << log_;
  }
  static std::string dir_, log_;
  static bool fused_;
};
std::string TexturedDance::dir_, TexturedDance::log_;
bool TexturedDance::fused_ = false;

TEST_F(TexturedDance, GlbHoldsATexturedSimplifiedMeshThatBlenderImportsUnpatched) {
  int status = 0;
  const std::string glb = dir_ + "/room.glb";
  const std::string out = run(kVdbfuse + " mesh " + dir_ + "/scene.vdb -o " + glb +
                                  " --exclude-classes person --texture --target-triangles 20000 -f",
                              status);
  ASSERT_EQ(status, 0) << out;
  EXPECT_NE(out.find("simplified"), std::string::npos) << out;
  // The scene recorded its capture and poses at reconstruct time: the bake found them there.
  EXPECT_NE(out.find("at the poses of the scene's metadata"), std::string::npos) << out;
  EXPECT_GT(numberAfter(out, "baked "), 100000) << out;
  // Most texels come from the frames, not from the fused colour.
  EXPECT_GT(numberAfter(out, "texels: "), 80.0) << out;
  const double triangles = numberAfter(out, "wrote " + glb + ": ");
  EXPECT_GT(triangles, 10000);
  EXPECT_LE(triangles, 20000);
  const nlohmann::json j = glbJson(glb);
  ASSERT_EQ(j["images"].size(), 1u) << j.dump();
  EXPECT_EQ(j["images"][0]["mimeType"], "image/jpeg");
  ASSERT_EQ(j["textures"].size(), 1u);
  for (const auto& mesh : j["meshes"])
    for (const auto& prim : mesh["primitives"]) {
      EXPECT_TRUE(prim["attributes"].contains("TEXCOORD_0"));
      EXPECT_FALSE(prim["attributes"].contains("COLOR_0")) << "vertex colours would tint the texture";
      const auto& material = j["materials"][prim["material"].get<size_t>()];
      EXPECT_EQ(material["pbrMetallicRoughness"]["baseColorTexture"]["index"], 0);
    }
  if (!haveBlender()) GTEST_SKIP() << "blender is not installed: the GLB was not imported";
  const std::string imported = run("blender -b --factory-startup --python " + kScripts + "count_import.py -- " + glb, status);
  ASSERT_EQ(status, 0) << imported;
  EXPECT_NE(imported.find("vdbfuse: imported 1 objects "), std::string::npos) << imported;
  EXPECT_NE(imported.find("vdbfuse: uv layers 1 images "), std::string::npos) << imported;
  EXPECT_EQ(imported.find("images -"), std::string::npos) << "no image texture arrived:\n" << imported;
  EXPECT_LT(numberAfter(imported, "import seconds "), 3.0) << imported;
}

TEST_F(TexturedDance, ObjWritesItsImageAndMaterialBeside) {
  int status = 0;
  const std::string obj = dir_ + "/room.obj";
  const std::string out = run(kVdbfuse + " mesh " + dir_ + "/scene.vdb -o " + obj +
                                  " --texture --texture-format png --target-triangles 20000 -f",
                              status);
  ASSERT_EQ(status, 0) << out;
  ASSERT_TRUE(fs::exists(dir_ + "/room.png"));
  std::ifstream mtl(dir_ + "/room.mtl");
  const std::string text((std::istreambuf_iterator<char>(mtl)), std::istreambuf_iterator<char>());
  EXPECT_NE(text.find("map_Kd room.png"), std::string::npos) << text;
  if (!haveBlender()) GTEST_SKIP() << "blender is not installed: the OBJ was not imported";
  const std::string imported = run("blender -b --factory-startup --python " + kScripts + "count_import.py -- " + obj, status);
  ASSERT_EQ(status, 0) << imported;
  EXPECT_NE(imported.find("vdbfuse: uv layers 1 images room.png:"), std::string::npos) << imported;
}

TEST_F(TexturedDance, BlenderFolderNamesTheTextureAndImportSceneWiresIt) {
  int status = 0;
  const std::string folder = dir_ + "/blend";
  const std::string out = run(kVdbfuse + " export " + dir_ + "/scene.vdb --blender -o " + folder +
                                  " --texture --target-triangles 20000 -f",
                              status);
  ASSERT_EQ(status, 0) << out;
  std::ifstream manifest_file(folder + "/scene.json");
  const nlohmann::json manifest = nlohmann::json::parse(manifest_file);
  ASSERT_EQ(manifest["texture"], "texture.jpg");
  EXPECT_TRUE(fs::exists(folder + "/texture.jpg"));
  for (const auto& m : manifest["meshes"]) EXPECT_EQ(fs::path(m["file"].get<std::string>()).extension(), ".obj");
  if (!haveBlender()) GTEST_SKIP() << "blender is not installed: import_scene.py was not run";
  const std::string imported =
      run("blender -b --factory-startup --python " + kScripts + "import_scene.py -- " + folder, status);
  ASSERT_EQ(status, 0) << imported;
  EXPECT_NE(imported.find("vdbfuse: imported "), std::string::npos) << imported;
}

// Debian 12's Blender 3.4 glTF add-on fails on its default shading path whatever the file holds
// (np.bool, removed from numpy 1.24); the "Smooth" option imports the same file. README's GLB
// row says so. Should a fixed Blender import with the default too, this still passes.
TEST_F(TexturedDance, GltfDefaultShadingFailsOnlyWithTheNumpyAliasError) {
  if (!haveBlender()) GTEST_SKIP() << "blender is not installed";
  int status = 0;
  const std::string glb = dir_ + "/plain.glb";
  ASSERT_EQ((run(kVdbfuse + " mesh " + dir_ + "/scene.vdb -o " + glb + " --target-triangles 5000 -f", status), status), 0);
  const std::string smooth = run("blender -b --factory-startup --python " + kScripts + "count_import.py -- " + glb, status);
  EXPECT_EQ(status, 0) << smooth;
  EXPECT_NE(smooth.find("vdbfuse: imported 1 objects"), std::string::npos) << smooth;
  const std::string normals = run("blender -b --factory-startup --python-exit-code 1 --python " + kScripts +
                                      "count_import.py -- " + glb + " --gltf-shading NORMALS",
                                  status);
  if (normals.find("vdbfuse: imported 1 objects") == std::string::npos)
    EXPECT_NE(normals.find("has no attribute 'bool'"), std::string::npos) << normals;
}

// TUM fr1/xyz (100 frames, ICP): the textured GLB under 200 k triangles, its shape within 5 mm
// (90th percentile, both ways) of the full marching-cubes mesh.
TEST(TexturedTum, SimplifiedSurfaceStaysWithinFiveMillimetres) {
  VF_REQUIRE_DATA(folder, "tum_fr1_xyz_head100");
  const std::string dir = test::tempDir("textured_tum");
  int status = 0;
  std::string out = run(kVdbfuse + " reconstruct " + folder + " --device cpu -q -o " + dir + "/scene.vdb", status);
  ASSERT_EQ(status, 0) << out;
  out = run(kVdbfuse + " mesh " + dir + "/scene.vdb -o " + dir + "/full.ply", status);
  ASSERT_EQ(status, 0) << out;
  out = run(kVdbfuse + " mesh " + dir + "/scene.vdb -o " + dir + "/simple.ply --target-triangles 200000", status);
  ASSERT_EQ(status, 0) << out;
  const TriangleMesh full = readPly(dir + "/full.ply"), simple = readPly(dir + "/simple.ply");
  ASSERT_GT(full.triangleCount(), 400000u);
  EXPECT_LE(simple.triangleCount(), 200000u);
  auto p90 = [](std::vector<float> d) {
    std::nth_element(d.begin(), d.begin() + long(d.size() * 9 / 10), d.end());
    return d[d.size() * 9 / 10];
  };
  const float a = p90(TriangleBvh(simple).distances(sampleSurface(full, 300000)));
  const float b = p90(TriangleBvh(full).distances(sampleSurface(simple, 300000)));
  std::printf("TUM fr1/xyz: %zu -> %zu triangles, p90 %.2f mm / %.2f mm\n", full.triangleCount(), simple.triangleCount(),
              a * 1000, b * 1000);
  EXPECT_LT(a, 0.005f);
  EXPECT_LT(b, 0.005f);
  out = run(kVdbfuse + " mesh " + dir + "/scene.vdb -o " + dir + "/room.glb --texture --target-triangles 200000", status);
  ASSERT_EQ(status, 0) << out;
  EXPECT_GT(numberAfter(out, "texels: "), 80.0) << out;
}

}  // namespace
}  // namespace vf
