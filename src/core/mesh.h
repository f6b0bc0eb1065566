#pragma once
// A plain indexed triangle mesh shared by the mesher (src/vdb) and the writers (io/mesh_io).
#include <array>
#include <cstdint>
#include <vector>

#include "core/math.h"

namespace vf {

struct TriangleMesh {
  std::vector<Vec3f> positions;   // metres, world frame
  std::vector<Vec3f> normals;     // unit, pointing out of the surface; empty or one per vertex
  std::vector<Rgb8> colors;       // sRGB 8 bit; empty or one per vertex
  std::vector<int32_t> classes;   // per-vertex class id (-1 unknown); empty when not known
  std::vector<Vec2f> uvs;         // texture coordinates 0..1, v up (OBJ's convention); empty or one per vertex
  std::vector<std::array<int32_t, 3>> triangles;  // counter-clockwise seen from outside

  size_t vertexCount() const { return positions.size(); }
  size_t triangleCount() const { return triangles.size(); }
  bool hasNormals() const { return !normals.empty(); }
  bool hasColors() const { return !colors.empty(); }
  bool hasClasses() const { return !classes.empty(); }
  bool hasUvs() const { return !uvs.empty(); }
};

}  // namespace vf
