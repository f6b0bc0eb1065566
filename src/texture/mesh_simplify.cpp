// Simplification through meshoptimizer: weld, collapse, compact.
#include "texture/mesh_simplify.h"

#include <meshoptimizer.h>

#include <algorithm>
#include <vector>

#include "core/error.h"

namespace vf {
namespace {

// The mesh with vertices at bit-equal positions merged (the first one's attributes kept): the
// simplifier sees a split vertex as a border, which it may not collapse across.
TriangleMesh weldByPosition(const TriangleMesh& mesh, size_t* merged) {
  std::vector<unsigned> remap(mesh.vertexCount());
  const size_t unique = meshopt_generateVertexRemap(remap.data(), nullptr, mesh.vertexCount(), mesh.positions.data(),
                                                    mesh.vertexCount(), sizeof(Vec3f));
  *merged = mesh.vertexCount() - unique;
  if (unique == mesh.vertexCount()) return mesh;
  TriangleMesh out;
  out.positions.resize(unique);
  if (mesh.hasNormals()) out.normals.resize(unique);
  if (mesh.hasColors()) out.colors.resize(unique);
  if (mesh.hasClasses()) out.classes.resize(unique);
  std::vector<bool> set(unique, false);
  for (size_t v = 0; v < mesh.vertexCount(); ++v) {
    const unsigned u = remap[v];
    if (set[u]) continue;
    set[u] = true;
    out.positions[u] = mesh.positions[v];
    if (mesh.hasNormals()) out.normals[u] = mesh.normals[v];
    if (mesh.hasColors()) out.colors[u] = mesh.colors[v];
    if (mesh.hasClasses()) out.classes[u] = mesh.classes[v];
  }
  out.triangles.reserve(mesh.triangleCount());
  for (const auto& t : mesh.triangles) {
    const std::array<int32_t, 3> w{int32_t(remap[size_t(t[0])]), int32_t(remap[size_t(t[1])]), int32_t(remap[size_t(t[2])])};
    if (w[0] != w[1] && w[1] != w[2] && w[0] != w[2]) out.triangles.push_back(w);  // welding can close a sliver
  }
  return out;
}

// The vertices `indices` use, renumbered in first-use order.
TriangleMesh compact(const TriangleMesh& mesh, const std::vector<unsigned>& indices) {
  TriangleMesh out;
  std::vector<int32_t> remap(mesh.vertexCount(), -1);
  out.triangles.resize(indices.size() / 3);
  for (size_t i = 0; i < indices.size(); ++i) {
    const unsigned v = indices[i];
    if (remap[v] < 0) {
      remap[v] = int32_t(out.positions.size());
      out.positions.push_back(mesh.positions[v]);
      if (mesh.hasNormals()) out.normals.push_back(mesh.normals[v]);
      if (mesh.hasColors()) out.colors.push_back(mesh.colors[v]);
      if (mesh.hasClasses()) out.classes.push_back(mesh.classes[v]);
    }
    out.triangles[i / 3][i % 3] = remap[v];
  }
  return out;
}

}  // namespace

TriangleMesh simplifyMesh(const TriangleMesh& input, const SimplifyOptions& options, SimplifyReport* report) {
  if (options.target_triangles < 1) throw Error("simplify: the target must be at least one triangle");
  if (!(options.max_error_m >= 0)) throw Error("simplify: the error bound must be >= 0 metres");
  SimplifyReport r;
  r.triangles_before = input.triangleCount();
  TriangleMesh mesh = weldByPosition(input, &r.vertices_welded);
  if (mesh.triangleCount() > options.target_triangles) {
    std::vector<unsigned> indices(mesh.triangleCount() * 3);
    for (size_t f = 0; f < mesh.triangleCount(); ++f)
      for (int k = 0; k < 3; ++k) indices[f * 3 + size_t(k)] = unsigned(mesh.triangles[f][size_t(k)]);
    // meshoptimizer's error is relative to the mesh's extent.
    const float scale = meshopt_simplifyScale(&mesh.positions[0].x, mesh.vertexCount(), sizeof(Vec3f));
    const float relative = options.max_error_m > 0 && scale > 0 ? options.max_error_m / scale : 1.f;
    std::vector<unsigned> kept(indices.size());
    float error = 0;
    kept.resize(meshopt_simplify(kept.data(), indices.data(), indices.size(), &mesh.positions[0].x, mesh.vertexCount(),
                                 sizeof(Vec3f), options.target_triangles * 3, relative, 0, &error));
    r.error_m = error * scale;
    mesh = compact(mesh, kept);
  }
  r.triangles_after = mesh.triangleCount();
  if (report) *report = r;
  return mesh;
}

}  // namespace vf
