#include "vdb/brick_surface.h"

#include <tbb/parallel_for.h>

#include <algorithm>
#include <numeric>
#include <unordered_map>
#include <vector>

#include "vdb/surface_point.h"

namespace vf {
namespace {

uint64_t coordHash(int x, int y, int z) {  // splitmix64 over the packed coordinates
  uint64_t h = (uint64_t(uint32_t(x)) << 42) ^ (uint64_t(uint32_t(y)) << 21) ^ uint64_t(uint32_t(z));
  h = (h ^ (h >> 30)) * 0xBF58476D1CE4E5B9ull;
  h = (h ^ (h >> 27)) * 0x94D049BB133111EBull;
  return h ^ (h >> 31);
}

struct BrickCoordHash {
  size_t operator()(const Vec3i& b) const { return size_t(coordHash(b.x, b.y, b.z)); }
};
struct BrickCoordEqual {
  bool operator()(const Vec3i& a, const Vec3i& b) const { return a.x == b.x && a.y == b.y && a.z == b.z; }
};

constexpr size_t kBricksPerTask = 256;

}  // namespace

TriangleMesh brickSurfaceSamples(const BrickVolumeView& v, int keep_one_in) {
  std::unordered_map<Vec3i, size_t, BrickCoordHash, BrickCoordEqual> brick_at;
  brick_at.reserve(v.brick_count);
  for (size_t n = 0; n < v.brick_count; ++n) brick_at.emplace(v.coords[n], n);
  const float sdf_scale = v.truncation_m / kTsdfScale;  // as the grids' values (vdb/brick_leaves.h)
  const double voxel = double(v.voxel_size_m);

  // The bricks beside brick n across each face ([axis][0: below, 1: above]; kNoBrick where none),
  // looked up once per brick: more than half of a brick's voxels have a 6-neighbour in another.
  constexpr size_t kNoBrick = ~size_t(0);
  struct FaceNeighbours {
    size_t across[3][2];
  };
  auto faceNeighbours = [&](const Vec3i& b) {
    FaceNeighbours f;
    for (int axis = 0; axis < 3; ++axis)
      for (int side = 0; side < 2; ++side) {
        Vec3i c = b;
        (axis == 0 ? c.x : axis == 1 ? c.y : c.z) += side ? 1 : -1;
        const auto it = brick_at.find(c);
        f.across[axis][side] = it == brick_at.end() ? kNoBrick : it->second;
      }
    return f;
  };
  // The signed distance of voxel (x, y, z), a 6-neighbour of a voxel of brick `home`, when that
  // voxel is observed (weight > 0).
  auto observed = [&](size_t home, const Vec3i& home_brick, const FaceNeighbours& faces, int x, int y, int z,
                      float& value) {
    const Vec3i b = brickOfVoxel(x, y, z);
    size_t n = home;
    if (b.x != home_brick.x) n = faces.across[0][b.x > home_brick.x];
    else if (b.y != home_brick.y) n = faces.across[1][b.y > home_brick.y];
    else if (b.z != home_brick.z) n = faces.across[2][b.z > home_brick.z];
    if (n == kNoBrick) return false;
    const TsdfVoxel t = v.tsdf[n * kBrickVoxels + size_t(localVoxelIndex(x, y, z))];
    value = float(t.tsdf) * sdf_scale;
    return t.weight > 0;
  };

  // Bricks in the order of their coordinates, not of their pool slots: slots are handed out
  // in whatever order the threads of integration got to them, and the samples' order decides
  // what a later fit (the floor plane) picks, which then differed from run to run.
  std::vector<size_t> order(v.brick_count);
  std::iota(order.begin(), order.end(), size_t(0));
  std::sort(order.begin(), order.end(), [&](size_t a, size_t b) {
    const Vec3i& p = v.coords[a];
    const Vec3i& q = v.coords[b];
    return p.z != q.z ? p.z < q.z : p.y != q.y ? p.y < q.y : p.x < q.x;
  });
  std::vector<TriangleMesh> parts((v.brick_count + kBricksPerTask - 1) / kBricksPerTask);
  tbb::parallel_for(size_t(0), parts.size(), [&](size_t task) {
    TriangleMesh& out = parts[task];
    const size_t end = std::min(v.brick_count, (task + 1) * kBricksPerTask);
    for (size_t k = task * kBricksPerTask; k < end; ++k) {
      const size_t n = order[k];
      const Vec3i b = v.coords[n];
      const FaceNeighbours faces = faceNeighbours(b);
      for (int i = 0; i < kBrickVoxels; ++i) {
        const TsdfVoxel t = v.tsdf[n * kBrickVoxels + size_t(i)];
        if (t.weight == 0) continue;
        const Vec3i l = localVoxelOffset(i);
        const int x = b.x * kBrickSize + l.x, y = b.y * kBrickSize + l.y, z = b.z * kBrickSize + l.z;
        if (keep_one_in > 1 && coordHash(x, y, z) % uint64_t(keep_one_in) != 0) continue;
        const float value = float(t.tsdf) * sdf_scale;
        std::array<double, 3> nrm;
        const bool on_surface = surfaceSample(value, voxel, [&](int axis, int side, float& neighbour) {
          return observed(n, b, faces, x + (axis == 0 ? side : 0), y + (axis == 1 ? side : 0), z + (axis == 2 ? side : 0),
                          neighbour);
        }, nrm);
        if (!on_surface) continue;
        // The cell-centred transform of the grids (vdb/scene.cpp sceneTransform), in double.
        const double centre[3] = {double(x) * voxel + 0.5 * voxel, double(y) * voxel + 0.5 * voxel,
                                  double(z) * voxel + 0.5 * voxel};
        out.positions.push_back({float(centre[0] - nrm[0] * double(value)), float(centre[1] - nrm[1] * double(value)),
                                 float(centre[2] - nrm[2] * double(value))});
        out.normals.push_back({float(nrm[0]), float(nrm[1]), float(nrm[2])});
      }
    }
  });
  TriangleMesh samples;
  size_t total = 0;
  for (const TriangleMesh& p : parts) total += p.positions.size();
  samples.positions.reserve(total);
  samples.normals.reserve(total);
  for (const TriangleMesh& p : parts) {
    samples.positions.insert(samples.positions.end(), p.positions.begin(), p.positions.end());
    samples.normals.insert(samples.normals.end(), p.normals.begin(), p.normals.end());
  }
  return samples;
}

}  // namespace vf
