// `vdbfuse export --blender` end to end, and the Blender import script when Blender is installed.
#include <gtest/gtest.h>

#include <cstdio>
#include <cstdlib>
#include <filesystem>
#include <string>

#include "io/mesh_io.h"
#include "synthetic_scene.h"
#include "test_data.h"
#include "vdb/mesher.h"
#include "vdb/scene.h"

namespace vf {
namespace {

namespace fs = std::filesystem;

std::string run(const std::string& command, int& status) { return test::runCommand(command, status); }

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
  int status = 0;
  run("command -v blender", status);
  if (status != 0) GTEST_SKIP() << "blender is not installed: the import script was not run";
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
  EXPECT_TRUE(fs::exists(dir + "/scene.blend")) << out;
}

// Every mesh format the exporter writes arrives in Blender with its faces (Blender merges the
// vertices an OBJ/GLB writer repeats at class seams, so vertices may only shrink there).
TEST(BlenderExport, PlyObjAndGlbImportWithTheirFaces) {
  int status = 0;
  run("command -v blender", status);
  if (status != 0) GTEST_SKIP() << "blender is not installed: the imports were not run";
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

}  // namespace
}  // namespace vf
