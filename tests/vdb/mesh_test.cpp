// Marching cubes on the scene, class filters, per-class split, small pieces, mesh files.
#include <gtest/gtest.h>

#include <assimp/Importer.hpp>
#include <assimp/postprocess.h>
#include <assimp/scene.h>

#include <nlohmann/json.hpp>

#include <array>
#include <cmath>
#include <cstring>
#include <filesystem>
#include <fstream>
#include <iterator>
#include <map>
#include <set>

#include "core/color.h"
#include "core/error.h"
#include "io/mesh_io.h"
#include "synthetic_scene.h"
#include "test_data.h"
#include "vdb/class_selection.h"
#include "vdb/mesh_ops.h"
#include "vdb/mesher.h"
#include "vdb/scene.h"

namespace vf {
namespace {

using test::fillSdf;
using test::sphereSdf;
using test::sphereSpec;

constexpr float kRadius = 0.2f, kVoxel = 0.01f;

Scene sphereScene() {
  test::SyntheticVolume volume(sphereSpec(), true);
  fillSdf(volume, sphereSdf({0, 0, 0}, kRadius), 0.f);
  SceneMetadata meta;
  meta.classes.classes = {{test::kClassLeft, "chair", {255, 0, 0, 255}}, {test::kClassRight, "table", {0, 0, 255, 255}}};
  return sceneFromBricks(volume.view(), meta);
}

// Every undirected edge is used by exactly two faces, once in each direction.
bool isClosedManifold(const TriangleMesh& mesh) {
  std::map<std::pair<int, int>, int> directed;
  for (const auto& t : mesh.triangles)
    for (int k = 0; k < 3; ++k) ++directed[{t[k], t[(k + 1) % 3]}];
  for (const auto& [e, n] : directed) {
    if (n != 1) return false;
    auto it = directed.find({e.second, e.first});
    if (it == directed.end() || it->second != 1) return false;
  }
  return true;
}

TEST(Mesher, SphereVerticesLieOnTheRadiusAndTheSurfaceIsClosed) {
  const Scene scene = sphereScene();
  const TriangleMesh mesh = meshScene(scene);
  ASSERT_GT(mesh.triangleCount(), 5000u);
  float worst = 0;
  size_t outward = 0;
  for (size_t v = 0; v < mesh.vertexCount(); ++v) {
    const float r = norm(mesh.positions[v]);
    worst = std::max(worst, std::fabs(r - kRadius));
    outward += dot(mesh.normals[v], mesh.positions[v]) > 0;
  }
  EXPECT_LT(worst, kVoxel) << "vertex off the sphere by more than a voxel";
  EXPECT_LT(worst, 0.002f) << "linear interpolation of an exact SDF should be within 2 mm";
  EXPECT_EQ(outward, mesh.vertexCount()) << "normals must point out of the surface";
  EXPECT_TRUE(isClosedManifold(mesh));
  // Area of a sphere of 0.2 m: 0.503 m^2.
  double area = 0;
  for (const auto& t : mesh.triangles)
    area += 0.5 * norm(cross(mesh.positions[t[1]] - mesh.positions[t[0]], mesh.positions[t[2]] - mesh.positions[t[0]]));
  EXPECT_NEAR(area, 4 * M_PI * kRadius * kRadius, 0.01);
  // Colors: left half red-ish (200,40,30), right half green-ish (30,180,60); classes by half.
  for (size_t v = 0; v < mesh.vertexCount(); ++v) {
    if (std::fabs(mesh.positions[v].x) < 1.5f * kVoxel) continue;
    const bool left = mesh.positions[v].x < 0;
    EXPECT_EQ(mesh.classes[v], left ? test::kClassLeft : test::kClassRight);
    EXPECT_NEAR(mesh.colors[v].r, left ? 200 : 30, 1);
    EXPECT_NEAR(mesh.colors[v].g, left ? 40 : 180, 1);
  }
}

TEST(Mesher, MinWeightMasksWeaklyObservedVoxels) {
  test::SyntheticVolume volume(sphereSpec(), false);
  fillSdf(volume, sphereSdf({0, 0, 0}, kRadius), 0.f, 10);
  fillSdf(volume, sphereSdf({0.22f, 0.22f, 0.22f}, 0.05f), 0.f, 1);  // weak blob
  const Scene scene = sceneFromBricks(volume.view(), {});
  const TriangleMesh all = meshScene(scene);
  MeshOptions strict;
  strict.min_weight = 2;
  const TriangleMesh strong = meshScene(scene, strict);
  EXPECT_LT(strong.triangleCount(), all.triangleCount());
  for (const Vec3f& p : strong.positions) EXPECT_NEAR(norm(p), kRadius, kVoxel);
}

TEST(MeshOps, ExcludeRemovesExactlyThatClassAndPerClassSumsToTheWhole) {
  const Scene scene = sphereScene();
  const TriangleMesh mesh = meshScene(scene);
  const std::vector<int32_t> classes = faceClasses(mesh);
  const size_t left_faces = size_t(std::count(classes.begin(), classes.end(), test::kClassLeft));
  ASSERT_GT(left_faces, 1000u);

  const std::set<int> chair = resolveClassSelection(scene.meta.classes, {"chair"}, "--exclude-classes");
  const TriangleMesh without = filterFacesByClass(mesh, chair, false);
  EXPECT_EQ(without.triangleCount(), mesh.triangleCount() - left_faces);
  for (int32_t c : faceClasses(without)) EXPECT_NE(c, test::kClassLeft);

  const auto parts = splitByClass(mesh);
  size_t sum = 0;
  for (const auto& [id, part] : parts) sum += part.triangleCount();
  EXPECT_EQ(parts.size(), 2u);
  EXPECT_EQ(sum, mesh.triangleCount());
  EXPECT_EQ(parts.at(test::kClassLeft).triangleCount(), left_faces);

  // By id too; unknown names list the valid ones; an empty selection is an error.
  EXPECT_EQ(resolveClassSelection(scene.meta.classes, {"2"}, "--include-classes"), std::set<int>{2});
  try {
    resolveClassSelection(scene.meta.classes, {"sofa"}, "--include-classes");
    FAIL();
  } catch (const Error& e) {
    EXPECT_NE(std::string(e.what()).find("chair (1), table (2)"), std::string::npos) << e.what();
  }
  EXPECT_THROW(resolveClassSelection(scene.meta.classes, {""}, "--include-classes"), Error);
  EXPECT_THROW(filterFacesByClass(mesh, {1, 2}, false), Error);  // excluding everything
}

TEST(MeshOps, MinComponentDropsSmallPieces) {
  test::SyntheticVolume volume(sphereSpec(), false);
  fillSdf(volume, sphereSdf({0, 0, 0}, kRadius), 0.f);
  fillSdf(volume, sphereSdf({0.25f, 0.25f, 0.25f}, 0.03f), 0.f);
  const Scene scene = sceneFromBricks(volume.view(), {});
  TriangleMesh mesh = meshScene(scene);
  const size_t before = mesh.triangleCount();
  const ComponentStats stats = meshComponents(mesh, 2000);
  EXPECT_EQ(stats.pieces, 2u);
  EXPECT_EQ(stats.small, 1u);
  const size_t removed = removeSmallComponents(mesh, 2000);
  EXPECT_GT(removed, 100u);
  EXPECT_EQ(removed, stats.small_triangles);
  EXPECT_EQ(mesh.triangleCount(), before - removed);
  EXPECT_EQ(meshComponents(mesh, 2000).pieces, 1u);
  for (const Vec3f& p : mesh.positions) EXPECT_NEAR(norm(p), kRadius, kVoxel);
}

// Re-import through Assimp; JoinIdenticalVertices undoes the per-corner copies OBJ readers make.
const aiScene* import(Assimp::Importer& importer, const std::string& path) {
  const aiScene* s = importer.ReadFile(path, aiProcess_JoinIdenticalVertices);
  EXPECT_NE(s, nullptr) << path << ": " << importer.GetErrorString();
  return s;
}

TEST(MeshFiles, PlyObjGlbReimportWithSameCountsAndColors) {
  const Scene scene = sphereScene();
  const TriangleMesh mesh = meshScene(scene);
  const std::string dir = test::tempDir("mesh_files");
  MeshWriteOptions options;
  options.classes = &scene.meta.classes;
  options.with_class_property = true;
  for (const char* name : {"m.ply", "m.obj", "m.glb"}) {
    const std::string path = dir + "/" + name;
    writeMesh(mesh, path, options);
    Assimp::Importer importer;
    const aiScene* s = import(importer, path);
    ASSERT_NE(s, nullptr);
    size_t faces = 0, vertices = 0;
    std::map<std::tuple<int, int, int>, aiColor4D> colors;
    for (unsigned m = 0; m < s->mNumMeshes; ++m) {
      const aiMesh* am = s->mMeshes[m];
      faces += am->mNumFaces;
      vertices += am->mNumVertices;
      ASSERT_TRUE(am->HasVertexColors(0)) << name;
      for (unsigned v = 0; v < am->mNumVertices; ++v) {
        const aiVector3D p = am->mVertices[v];
        const aiColor4D c = am->mColors[0][v];
        colors[{int(std::lround(p.x * 1e4)), int(std::lround(p.y * 1e4)), int(std::lround(p.z * 1e4))}] = c;
      }
    }
    EXPECT_EQ(faces, mesh.triangleCount()) << name;
    // PLY keeps one vertex array; OBJ/GLB split per class, so seam vertices appear in both parts.
    if (std::string(name) == "m.ply") {
      EXPECT_EQ(vertices, mesh.vertexCount());
    }
    EXPECT_GE(vertices, mesh.vertexCount()) << name;
    EXPECT_LT(vertices, mesh.vertexCount() * 11 / 10) << name;
    size_t checked = 0;
    for (size_t v = 0; v < mesh.vertexCount(); v += 97) {
      const Vec3f p = mesh.positions[v];
      auto it = colors.find({int(std::lround(p.x * 1e4)), int(std::lround(p.y * 1e4)), int(std::lround(p.z * 1e4))});
      if (it == colors.end()) continue;
      // PLY and OBJ vertex colours are sRGB; glTF's COLOR_0 is linear.
      const bool linear = std::string(name) == "m.glb";
      const Rgb8 want = mesh.colors[v];
      EXPECT_NEAR(it->second.r, linear ? srgb8ToLinear(want.r) : want.r / 255.f, 0.5f / 255) << name;
      EXPECT_NEAR(it->second.g, linear ? srgb8ToLinear(want.g) : want.g / 255.f, 0.5f / 255) << name;
      ++checked;
    }
    EXPECT_GT(checked, mesh.vertexCount() / 97 / 2) << name;
  }
  // Our own PLY reader keeps the class property.
  const TriangleMesh back = readPly(dir + "/m.ply");
  EXPECT_EQ(back.triangles, mesh.triangles);
  EXPECT_EQ(back.classes, mesh.classes);
  EXPECT_EQ(back.colors.size(), mesh.colors.size());
  EXPECT_EQ(std::distance(std::filesystem::directory_iterator(dir), std::filesystem::directory_iterator()), 4)
      << "m.ply, m.obj, m.mtl, m.glb and no temp files";
  EXPECT_THROW(writeMesh(mesh, dir + "/m.stl"), Error);
}

// A PLY records the frame it was written in, exactly enough to undo; other tools' files and
// vdbfuse's older ones record none, and a damaged record is refused by name.
TEST(MeshFiles, PlyRecordsItsFrameAndReadingItBackUndoesTheRotation) {
  const std::string dir = test::tempDir("ply_frame");
  TriangleMesh mesh;
  mesh.positions = {{0.1f, -0.7f, 2.3f}, {1.4f, 0.2f, 1.9f}, {-0.6f, 0.5f, 3.1f}};
  mesh.normals = {{0, 0, -1}, {0, 0, -1}, {0, 0, -1}};
  mesh.triangles = {{0, 1, 2}};
  const float c = std::cos(0.7f), s = std::sin(0.7f);
  MeshFrame z_up{"z-up", Rigid3f{{1, 0, 0, 0, c, -s, 0, s, c}, {0.5f, 0, -1}}};
  TriangleMesh in_file = mesh;
  for (Vec3f& p : in_file.positions) p = z_up.file_from_scene * p;
  for (Vec3f& n : in_file.normals) n = z_up.file_from_scene.rotate(n);
  MeshWriteOptions write;
  write.frame = z_up;
  writeMesh(in_file, dir + "/z.ply", write);
  writePly(mesh, dir + "/plain.ply", false);

  std::optional<MeshFrame> frame;
  const TriangleMesh as_written = readPly(dir + "/z.ply", &frame);
  ASSERT_TRUE(frame.has_value());
  EXPECT_EQ(frame->axes, "z-up");
  EXPECT_NE(as_written.positions[0].y, mesh.positions[0].y);  // rotated
  std::string note;
  const TriangleMesh back = readPlyInSceneFrame(dir + "/z.ply", &note);
  EXPECT_EQ(note, "written --axes z-up, brought back into the scene's frame");
  for (size_t v = 0; v < mesh.positions.size(); ++v) {
    EXPECT_NEAR(back.positions[v].x, mesh.positions[v].x, 1e-6f);
    EXPECT_NEAR(back.positions[v].y, mesh.positions[v].y, 1e-6f);
    EXPECT_NEAR(back.positions[v].z, mesh.positions[v].z, 1e-6f);
    EXPECT_NEAR(back.normals[v].z, -1.f, 1e-6f);
  }
  readPly(dir + "/plain.ply", &frame);
  EXPECT_FALSE(frame.has_value());
  EXPECT_EQ(readPlyInSceneFrame(dir + "/plain.ply", &note).positions[0].y, mesh.positions[0].y);
  EXPECT_EQ(note, "as written");

  // The record with a number missing: an error naming the file, not a silently wrong frame.
  std::ifstream in(dir + "/z.ply", std::ios::binary);
  const std::string written((std::istreambuf_iterator<char>(in)), std::istreambuf_iterator<char>());
  std::string bytes = written;
  const size_t at = bytes.find(" -1\nelement vertex");
  ASSERT_NE(at, std::string::npos) << "the record ends with t.z = -1";
  bytes.erase(at, 3);
  std::ofstream(dir + "/bad.ply", std::ios::binary) << bytes;
  try {
    readPly(dir + "/bad.ply", &frame);
    ADD_FAILURE() << "a damaged frame record was read";
  } catch (const Error& e) {
    EXPECT_NE(std::string(e.what()).find("bad.ply: malformed 'vdbfuse frame'"), std::string::npos) << e.what();
  }
  // Twelve numbers, but a scale, not a rotation.
  bytes = written;
  const std::string record = "file_from_scene 1 0 0 ";
  const size_t r = bytes.find(record);
  ASSERT_NE(r, std::string::npos);
  bytes.replace(r, record.size(), "file_from_scene 2 0 0 ");
  std::ofstream(dir + "/scaled.ply", std::ios::binary) << bytes;
  try {
    readPly(dir + "/scaled.ply", &frame);
    ADD_FAILURE() << "a scale was taken for a rotation";
  } catch (const Error& e) {
    EXPECT_NE(std::string(e.what()).find("scaled.ply: the 'vdbfuse frame' header comment holds no rotation"),
              std::string::npos)
        << e.what();
  }
}

// The JSON chunk of a .glb (header 12 bytes, then chunk length, type "JSON", text).
nlohmann::json glbJson(const std::string& path) {
  std::ifstream in(path, std::ios::binary);
  std::string bytes((std::istreambuf_iterator<char>(in)), std::istreambuf_iterator<char>());
  EXPECT_GT(bytes.size(), 20u) << path;
  uint32_t length = 0;
  std::memcpy(&length, bytes.data() + 12, 4);
  return nlohmann::json::parse(bytes.substr(20, length));
}

// glTF's defaults: baseColorFactor [1, 1, 1, 1], metallicFactor 1, roughnessFactor 1.
std::array<float, 3> baseColor(const nlohmann::json& material) {
  const auto pbr = material.value("pbrMetallicRoughness", nlohmann::json::object());
  const auto c = pbr.value("baseColorFactor", nlohmann::json::array({1.0, 1.0, 1.0, 1.0}));
  return {c[0].get<float>(), c[1].get<float>(), c[2].get<float>()};
}

// Blender's glTF importer multiplies COLOR_0 by the base colour and its OBJ importer uses Kd alone:
// a class colour there painted the fused colours over (black for class 0, "background").
TEST(MeshFiles, MaterialsCarryNoClassColourWhereVertexColoursAre) {
  const Scene scene = sphereScene();
  const TriangleMesh mesh = meshScene(scene);
  const std::string dir = test::tempDir("mesh_materials");
  MeshWriteOptions options;
  options.classes = &scene.meta.classes;
  writeMesh(mesh, dir + "/rgb.glb", options);
  writeMesh(mesh, dir + "/rgb.obj", options);
  const nlohmann::json rgb = glbJson(dir + "/rgb.glb");
  ASSERT_EQ(rgb["materials"].size(), 2u);
  for (const auto& m : rgb["materials"]) {
    EXPECT_EQ(baseColor(m), (std::array<float, 3>{1, 1, 1})) << m;
    EXPECT_EQ(m["pbrMetallicRoughness"].value("metallicFactor", 1.0), 0.0) << "a scan is no metal: " << m;
    EXPECT_EQ(m["pbrMetallicRoughness"].value("roughnessFactor", 1.0), 1.0) << m;
  }
  for (const auto& mesh : rgb["meshes"])
    for (const auto& prim : mesh["primitives"]) EXPECT_TRUE(prim["attributes"].contains("COLOR_0"));
  // OBJ: each group's Kd is its mean colour (linear), close to neither class colour.
  std::ifstream mtl(dir + "/rgb.mtl");
  std::string word;
  std::vector<Vec3f> kd;
  while (mtl >> word)
    if (word == "Kd") {
      Vec3f c;
      mtl >> c.x >> c.y >> c.z;
      kd.push_back(c);
    }
  ASSERT_EQ(kd.size(), 2u);
  for (const Vec3f& c : kd) {
    // The sphere's fused colours: kColorLeft / kColorRight on the two halves (one per class).
    const Vec3f left = srgb8ToLinear(test::kColorLeft), right = srgb8ToLinear(test::kColorRight);
    EXPECT_LT(std::min(norm(c - left), norm(c - right)), 0.05f) << c.x << " " << c.y << " " << c.z;
  }

  // --color class: the class colour goes into the material, linear, and COLOR_0 stays out.
  MeshOptions by_class;
  by_class.color = MeshColorMode::kClass;
  options.class_colors = true;
  writeMesh(meshScene(scene, by_class), dir + "/class.glb", options);
  const nlohmann::json cls = glbJson(dir + "/class.glb");
  for (const auto& mesh : cls["meshes"])
    for (const auto& prim : mesh["primitives"]) EXPECT_FALSE(prim["attributes"].contains("COLOR_0"));
  std::set<std::array<float, 3>> bases;
  for (const auto& m : cls["materials"]) bases.insert(baseColor(m));
  for (const ClassInfo& c : scene.meta.classes.classes) {
    const Vec3f lin = srgb8ToLinear(c.color);
    EXPECT_EQ(bases.count({lin.x, lin.y, lin.z}), 1u) << c.name;
  }
}

}  // namespace
}  // namespace vf
