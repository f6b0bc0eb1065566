// Marching cubes on the scene, class filters, per-class split, small pieces, mesh files.
#include <gtest/gtest.h>

#include <assimp/Importer.hpp>
#include <assimp/postprocess.h>
#include <assimp/scene.h>

#include <cmath>
#include <filesystem>
#include <map>

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
  const size_t removed = removeSmallComponents(mesh, 2000);
  EXPECT_GT(removed, 100u);
  EXPECT_EQ(mesh.triangleCount(), before - removed);
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
    std::map<std::tuple<int, int, int>, Rgb8> colors;
    for (unsigned m = 0; m < s->mNumMeshes; ++m) {
      const aiMesh* am = s->mMeshes[m];
      faces += am->mNumFaces;
      vertices += am->mNumVertices;
      ASSERT_TRUE(am->HasVertexColors(0)) << name;
      for (unsigned v = 0; v < am->mNumVertices; ++v) {
        const aiVector3D p = am->mVertices[v];
        const aiColor4D c = am->mColors[0][v];
        colors[{int(std::lround(p.x * 1e4)), int(std::lround(p.y * 1e4)), int(std::lround(p.z * 1e4))}] =
            Rgb8{uint8_t(std::lround(c.r * 255)), uint8_t(std::lround(c.g * 255)), uint8_t(std::lround(c.b * 255)), 255};
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
      EXPECT_NEAR(it->second.r, mesh.colors[v].r, 1) << name;
      EXPECT_NEAR(it->second.g, mesh.colors[v].g, 1) << name;
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

}  // namespace
}  // namespace vf
