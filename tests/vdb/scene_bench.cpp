// Benchmark: 512^3 dense volume with a room-sized surface (floor, three walls, a table, two
// spheres; ~3 m at 5.9 mm voxels) -> sparse scene -> mesh. Prints timings; writes the scene to
// argv[1] (default /tmp/vdbfuse_bench_scene.vdb) so `vdbfuse mesh` can be timed on it.
#include <algorithm>
#include <chrono>
#include <cmath>
#include <cstdio>
#include <string>

#include "synthetic_scene.h"
#include "vdb/mesher.h"
#include "vdb/scene.h"

using namespace vf;

namespace {

float box(Vec3f p, Vec3f lo, Vec3f hi) {
  const Vec3f c = (lo + hi) * 0.5f, h = (hi - lo) * 0.5f;
  const Vec3f q{std::fabs(p.x - c.x) - h.x, std::fabs(p.y - c.y) - h.y, std::fabs(p.z - c.z) - h.z};
  const Vec3f m{std::max(q.x, 0.f), std::max(q.y, 0.f), std::max(q.z, 0.f)};
  return norm(m) + std::min(std::max(q.x, std::max(q.y, q.z)), 0.f);
}

float roomSdf(Vec3f p) {
  float d = p.z - 0.1f;                             // floor
  d = std::min(d, p.x - 0.1f);                      // walls (one-sided like a scan)
  d = std::min(d, p.y - 0.1f);
  d = std::min(d, 2.9f - p.x);
  d = std::min(d, box(p, {1.0f, 1.0f, 0.1f}, {2.0f, 1.8f, 0.8f}));  // table block
  d = std::min(d, norm(p - Vec3f{0.6f, 2.2f, 0.5f}) - 0.35f);
  d = std::min(d, norm(p - Vec3f{2.3f, 2.3f, 1.2f}) - 0.25f);
  return d;
}

double since(std::chrono::steady_clock::time_point t) {
  return std::chrono::duration<double>(std::chrono::steady_clock::now() - t).count();
}

}  // namespace

int main(int argc, char** argv) {
  const std::string out = argc > 1 ? argv[1] : "/tmp/vdbfuse_bench_scene.vdb";
  // A 3 m room at the default voxel (512^3 box voxels of 5.86 mm), filled slab by slab.
  test::SyntheticSpec spec;
  spec.dims = {512, 512, 512};
  spec.voxel_size_m = 3.0f / 512;
  spec.truncation_m = 5 * spec.voxel_size_m;
  spec.origin_vox = {0, 0, 0};
  test::SyntheticVolume volume(spec, true);
  HostBrickVolume& v = volume.bricks();
  auto t = std::chrono::steady_clock::now();
  for (int z = 0; z < spec.dims.z; ++z)
    for (int y = 0; y < spec.dims.y; ++y)
      for (int x = 0; x < spec.dims.x; ++x) {
        const Vec3f p = volume.voxelCenter(x, y, z);
        const float d = roomSdf(p);
        // Fusion only writes voxels in front of the surface up to the truncation, and behind it.
        if (std::fabs(d) >= spec.truncation_m) continue;
        const size_t i = volume.voxel(x, y, z);
        v.tsdf[i] = {int16_t(std::lround(d / spec.truncation_m * kTsdfScale)), uint16_t(5 + (x + y) % 20)};
        v.color[i] = {uint8_t(x / 2), uint8_t(y / 2), uint8_t(z / 2), 255};
        v.class_vote[i] = packClassVote(p.z < 0.15f ? 1u : p.z < 0.85f ? 2u : 3u, 9);
      }
  std::printf("fill (test setup)      %.2f s, %zu bricks\n", since(t), v.coords.size());

  SceneMetadata meta;
  meta.classes.classes = {{1, "floor", {120, 120, 120, 255}}, {2, "furniture", {160, 90, 40, 255}},
                          {3, "wall", {220, 220, 220, 255}}};
  meta.source = "scene_bench room";
  double best = 1e9;
  Scene scene;
  for (int rep = 0; rep < 3; ++rep) {
    t = std::chrono::steady_clock::now();
    scene = sceneFromBricks(volume.view(), meta);
    best = std::min(best, since(t));
  }
  std::printf("bricks -> grids        %.3f s (best of 3), %zu active voxels\n", best, scene.activeVoxelCount());
  t = std::chrono::steady_clock::now();
  writeScene(scene, out);
  std::printf("write %s  %.3f s\n", out.c_str(), since(t));
  t = std::chrono::steady_clock::now();
  const Scene back = readScene(out);
  std::printf("read                   %.3f s\n", since(t));
  t = std::chrono::steady_clock::now();
  const TriangleMesh mesh = meshScene(back);
  std::printf("marching cubes         %.3f s, %zu triangles, %zu vertices\n", since(t), mesh.triangleCount(),
              mesh.vertexCount());
  return 0;
}
