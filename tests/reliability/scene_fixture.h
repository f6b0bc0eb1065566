#pragma once
// A small scene file made in the test: a sphere in 1 cm voxels with two classes whose names
// become the same file name once sanitised ("a/b" and "a_b"), and its trajectory beside it.
#include <fstream>
#include <string>

#include "vdb/scene.h"
#include "vdb/synthetic_scene.h"

namespace vf::test {

// dims^3 voxels of voxel_m; the sphere fills 60 % of the box.
inline Scene twoClassSphereScene(int dims = 48, float voxel_m = 0.01f) {
  SyntheticVolume volume(sphereSpec(dims, voxel_m), /*with_classes=*/true);
  fillSdf(volume, sphereSdf({0, 0, 0}, 0.3f * dims * voxel_m), 0.f);
  SceneMetadata meta;
  meta.voxel_size_m = volume.spec().voxel_size_m;
  meta.truncation_m = volume.spec().truncation_m;
  meta.classes.classes = {{kClassLeft, "a/b", {200, 40, 30, 255}}, {kClassRight, "a_b", {30, 180, 60, 255}}};
  meta.source = "synthetic sphere";
  meta.frame_count = 1;
  return sceneFromBricks(volume.view(), meta);
}

// Writes dir/scene.vdb and dir/scene.txt (one pose); returns the scene's path.
inline std::string writeSceneFixture(const std::string& dir, int dims = 48, float voxel_m = 0.01f) {
  const std::string path = dir + "/scene.vdb";
  writeScene(twoClassSphereScene(dims, voxel_m), path);
  std::ofstream(dir + "/scene.txt") << "0.000000 0 0 0 0 0 0 1\n";
  return path;
}

}  // namespace vf::test
