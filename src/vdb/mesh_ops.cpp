#include "vdb/mesh_ops.h"

#include <algorithm>
#include <cctype>
#include <set>
#include <string>
#include <unordered_map>

#include "core/error.h"
#include "core/union_find.h"

namespace vf {

std::vector<int32_t> faceClasses(const TriangleMesh& mesh) {
  std::vector<int32_t> out(mesh.triangles.size(), -1);
  if (!mesh.hasClasses()) return out;
  for (size_t f = 0; f < mesh.triangles.size(); ++f) {
    const auto& t = mesh.triangles[f];
    const int32_t a = mesh.classes[t[0]], b = mesh.classes[t[1]], c = mesh.classes[t[2]];
    out[f] = (b == c && a != b) ? b : a;  // a==b or a==c -> a; b==c -> b; all differ -> a
  }
  return out;
}

TriangleMesh selectFaces(const TriangleMesh& mesh, const std::vector<bool>& keep) {
  TriangleMesh out;
  std::vector<int32_t> remap(mesh.positions.size(), -1);
  for (size_t f = 0; f < mesh.triangles.size(); ++f) {
    if (!keep[f]) continue;
    std::array<int32_t, 3> t{};
    for (int k = 0; k < 3; ++k) {
      const int32_t v = mesh.triangles[f][k];
      if (remap[v] < 0) remap[v] = 0;  // mark; numbered below to keep vertex order
      t[k] = v;
    }
    out.triangles.push_back(t);
  }
  int32_t next = 0;
  for (size_t v = 0; v < remap.size(); ++v) {
    if (remap[v] < 0) continue;
    remap[v] = next++;
    out.positions.push_back(mesh.positions[v]);
    if (mesh.hasNormals()) out.normals.push_back(mesh.normals[v]);
    if (mesh.hasColors()) out.colors.push_back(mesh.colors[v]);
    if (mesh.hasClasses()) out.classes.push_back(mesh.classes[v]);
    if (mesh.hasUvs()) out.uvs.push_back(mesh.uvs[v]);  // a textured export's per-class split
  }
  for (auto& t : out.triangles)
    for (int32_t& v : t) v = remap[v];
  return out;
}

TriangleMesh filterFacesByClass(const TriangleMesh& mesh, const std::set<int>& ids, bool include) {
  if (!mesh.hasClasses()) throw Error("class filter: the scene has no class grid (fused without labels)");
  const std::vector<int32_t> classes = faceClasses(mesh);
  std::vector<bool> keep(classes.size());
  for (size_t f = 0; f < classes.size(); ++f) keep[f] = (ids.count(classes[f]) > 0) == include;
  TriangleMesh out = selectFaces(mesh, keep);
  if (out.triangles.empty()) throw Error("class filter: the selection leaves no faces");
  return out;
}

std::map<int32_t, TriangleMesh> splitByClass(const TriangleMesh& mesh) {
  const std::vector<int32_t> classes = faceClasses(mesh);
  std::map<int32_t, TriangleMesh> out;
  std::set<int32_t> present(classes.begin(), classes.end());
  for (int32_t id : present) {
    std::vector<bool> keep(classes.size());
    for (size_t f = 0; f < classes.size(); ++f) keep[f] = classes[f] == id;
    out.emplace(id, selectFaces(mesh, keep));
  }
  return out;
}

std::vector<size_t> faceComponentSizes(const TriangleMesh& mesh) {
  // Faces sharing a vertex share a component.
  UnionFind pieces(mesh.positions.size());
  for (const auto& t : mesh.triangles)
    for (int k = 1; k < 3; ++k) pieces.unite(t[0], t[k]);
  const std::vector<int32_t>& root = pieces.flatten();
  std::vector<size_t> faces(root.size(), 0);
  for (const auto& t : mesh.triangles) ++faces[size_t(root[size_t(t[0])])];
  std::vector<size_t> out(mesh.triangles.size());
  for (size_t f = 0; f < mesh.triangles.size(); ++f) out[f] = faces[size_t(root[size_t(mesh.triangles[f][0])])];
  return out;
}

ComponentStats meshComponents(const TriangleMesh& mesh, size_t min_triangles) {
  ComponentStats stats;
  // Every face knows its piece's size n, so a piece of n faces shows up n times: count faces
  // by size and divide.
  std::map<size_t, size_t> faces_of_size;
  for (size_t size : faceComponentSizes(mesh)) ++faces_of_size[size];
  for (const auto& [size, faces] : faces_of_size) {
    stats.largest = std::max(stats.largest, size);
    if (size < min_triangles) stats.small_triangles += faces;
    stats.pieces += faces / size;
    if (size < min_triangles) stats.small += faces / size;
  }
  return stats;
}

size_t removeSmallComponents(TriangleMesh& mesh, size_t min_triangles) {
  if (min_triangles <= 1 || mesh.triangles.empty()) return 0;
  const std::vector<size_t> sizes = faceComponentSizes(mesh);
  std::vector<bool> keep(mesh.triangles.size());
  size_t removed = 0;
  for (size_t f = 0; f < mesh.triangles.size(); ++f) {
    keep[f] = sizes[f] >= min_triangles;
    removed += !keep[f];
  }
  if (removed) mesh = selectFaces(mesh, keep);
  return removed;
}

std::string classFileStem(const ClassTable& table, int32_t id) {
  const ClassInfo* c = table.findId(id);
  std::string name = c ? c->name : (id < 0 ? std::string("unknown") : "class_" + std::to_string(id));
  for (char& ch : name)
    if (!std::isalnum(static_cast<unsigned char>(ch)) && ch != '-' && ch != '_') ch = '_';
  return name.empty() ? "class_" + std::to_string(id) : name;
}

std::map<int32_t, std::string> uniqueClassFileStems(const ClassTable& table, const std::vector<int32_t>& ids) {
  std::map<int32_t, std::string> stems;
  std::set<std::string> taken;  // lower case: some file systems ignore case
  auto lower = [](std::string s) {
    for (char& c : s) c = char(std::tolower(static_cast<unsigned char>(c)));
    return s;
  };
  std::vector<int32_t> sorted = ids;
  std::sort(sorted.begin(), sorted.end());
  for (int32_t id : sorted) {
    std::string stem = classFileStem(table, id);
    for (int n = 0; taken.count(lower(stem)); ++n)
      stem = classFileStem(table, id) + "_" + std::to_string(id) + (n ? "_" + std::to_string(n) : "");
    taken.insert(lower(stem));
    stems[id] = stem;
  }
  return stems;
}

}  // namespace vf
