#include "room_mesh.h"

#include <algorithm>
#include <cmath>

#include "room_texture.h"

namespace vf::synth {
namespace {

constexpr float kMaxSagitta_m = 0.0005f;

Vec3f toVec3f(const Vec3& v) { return {v.x(), v.y(), v.z()}; }

struct MeshBuilder {
  const Room& room;
  TriangleMesh& mesh;
  std::vector<int>* triangle_primitive;
  int primitive = 0;

  int vertex(const Vec3& p, const Vec3& n) {
    mesh.positions.push_back(toVec3f(p));
    mesh.normals.push_back(toVec3f(n));
    const Vec3 c = surfaceColor(room.primitives[size_t(primitive)], p, n);
    mesh.colors.push_back(Rgb8{uint8_t(std::lround(c.x())), uint8_t(std::lround(c.y())), uint8_t(std::lround(c.z())), 255});
    return int(mesh.positions.size()) - 1;
  }
  void triangle(int a, int b, int c) {
    mesh.triangles.push_back({a, b, c});
    if (triangle_primitive) triangle_primitive->push_back(primitive);
  }
  // A grid over the rectangle corner + s*e1 + t*e2 (s, t in [0, 1]), counter-clockwise seen
  // from the side e1 x e2 points to, which must be `normal`.
  void rectangle(const Vec3& corner, const Vec3& e1, const Vec3& e2, const Vec3& normal, float max_edge) {
    const int n1 = std::max(1, int(std::ceil(e1.norm() / max_edge))), n2 = std::max(1, int(std::ceil(e2.norm() / max_edge)));
    const int first = int(mesh.positions.size());
    for (int j = 0; j <= n2; ++j)
      for (int i = 0; i <= n1; ++i) vertex(corner + e1 * (float(i) / float(n1)) + e2 * (float(j) / float(n2)), normal);
    auto id = [&](int i, int j) { return first + j * (n1 + 1) + i; };
    for (int j = 0; j < n2; ++j)
      for (int i = 0; i < n1; ++i) {
        triangle(id(i, j), id(i + 1, j), id(i + 1, j + 1));
        triangle(id(i, j), id(i + 1, j + 1), id(i, j + 1));
      }
  }
  void box(const Primitive& p, bool inward, float max_edge) {
    for (int a = 0; a < 3; ++a)
      for (int side = 0; side < 2; ++side) {
        const int b = (a + 1) % 3, c = (a + 2) % 3;
        Vec3 corner = p.lo;
        corner[a] = side ? p.hi[a] : p.lo[a];
        Vec3 eb = Vec3::Zero(), ec = Vec3::Zero();
        eb[b] = p.hi[b] - p.lo[b];
        ec[c] = p.hi[c] - p.lo[c];
        Vec3 normal = Vec3::Zero();
        normal[a] = (side == 1) != inward ? 1.f : -1.f;
        if (normal[a] > 0) rectangle(corner, eb, ec, normal, max_edge);  // e_b x e_c = +e_a
        else rectangle(corner, ec, eb, normal, max_edge);
      }
  }
  static int segments(float radius, float max_edge) {
    const int by_sagitta = int(std::ceil(float(M_PI) / std::acos(1.f - kMaxSagitta_m / radius)));
    const int by_edge = int(std::ceil(2.f * float(M_PI) * radius / max_edge));
    return std::max({16, by_sagitta, by_edge});
  }
  void sphere(const Primitive& p, float max_edge) {
    const int lon = segments(p.radius, max_edge), lat = std::max(8, lon / 2);
    const int first = int(mesh.positions.size());
    for (int i = 0; i <= lat; ++i)
      for (int j = 0; j <= lon; ++j) {
        const float theta = float(M_PI) * float(i) / float(lat), phi = 2.f * float(M_PI) * float(j) / float(lon);
        const Vec3 n(std::sin(theta) * std::cos(phi), std::sin(theta) * std::sin(phi), std::cos(theta));
        vertex(p.center + p.radius * n, n);
      }
    auto id = [&](int i, int j) { return first + i * (lon + 1) + j; };
    for (int i = 0; i < lat; ++i)
      for (int j = 0; j < lon; ++j) {
        if (i + 1 < lat) triangle(id(i, j), id(i + 1, j), id(i + 1, j + 1));  // not at the south pole
        if (i > 0) triangle(id(i, j), id(i + 1, j + 1), id(i, j + 1));         // not at the north pole
      }
  }
  void cylinder(const Primitive& p, float max_edge) {
    const int n = segments(p.radius, max_edge);
    const float z0 = p.lo.z(), z1 = p.hi.z();
    const int rows = std::max(1, int(std::ceil((z1 - z0) / max_edge)));
    const int first = int(mesh.positions.size());
    for (int k = 0; k <= rows; ++k)
      for (int j = 0; j <= n; ++j) {
        const float phi = 2.f * float(M_PI) * float(j) / float(n);
        const Vec3 radial(std::cos(phi), std::sin(phi), 0);
        vertex(Vec3(p.center.x(), p.center.y(), z0 + (z1 - z0) * float(k) / float(rows)) + p.radius * radial, radial);
      }
    auto id = [&](int k, int j) { return first + k * (n + 1) + j; };
    for (int k = 0; k < rows; ++k)
      for (int j = 0; j < n; ++j) {
        triangle(id(k, j), id(k, j + 1), id(k + 1, j + 1));
        triangle(id(k, j), id(k + 1, j + 1), id(k + 1, j));
      }
    for (int top = 0; top < 2; ++top) {
      const float z = top ? z1 : z0;
      const Vec3 normal(0, 0, top ? 1.f : -1.f);
      const int centre = vertex(Vec3(p.center.x(), p.center.y(), z), normal);
      const int ring = int(mesh.positions.size());
      for (int j = 0; j <= n; ++j) {
        const float phi = 2.f * float(M_PI) * float(j) / float(n);
        vertex(Vec3(p.center.x() + p.radius * std::cos(phi), p.center.y() + p.radius * std::sin(phi), z), normal);
      }
      for (int j = 0; j < n; ++j) {
        if (top) triangle(centre, ring + j, ring + j + 1);
        else triangle(centre, ring + j + 1, ring + j);
      }
    }
  }
};

}  // namespace

TriangleMesh groundTruthMesh(const Room& room, float max_edge_m, std::vector<int>* triangle_primitive) {
  TriangleMesh mesh;
  if (triangle_primitive) triangle_primitive->clear();
  MeshBuilder b{room, mesh, triangle_primitive};
  for (size_t i = 0; i < room.primitives.size(); ++i) {
    const Primitive& p = room.primitives[i];
    b.primitive = int(i);
    switch (p.kind) {
      case Primitive::Kind::kBox: b.box(p, false, max_edge_m); break;
      case Primitive::Kind::kShell: b.box(p, true, max_edge_m); break;
      case Primitive::Kind::kSphere: b.sphere(p, max_edge_m); break;
      case Primitive::Kind::kCylinder: b.cylinder(p, max_edge_m); break;
    }
  }
  return mesh;
}

TriangleMesh meshWithout(const TriangleMesh& mesh, const std::vector<int>& triangle_primitive, int left_out) {
  TriangleMesh out = mesh;  // vertices stay (unreferenced ones do not count as surface)
  out.triangles.clear();
  for (size_t t = 0; t < mesh.triangles.size(); ++t)
    if (triangle_primitive.at(t) != left_out) out.triangles.push_back(mesh.triangles[t]);
  return out;
}

}  // namespace vf::synth
