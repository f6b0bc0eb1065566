#pragma once
// Mesh and point-cloud files: PLY (binary little endian, own code, with optional per-vertex
// class property), OBJ (one group + material per class) and GLB (through Assimp).
// Every writer goes through a temp file in the target directory renamed into place.
#include <string>

#include "core/class_table.h"
#include "core/mesh.h"

namespace vf {

enum class MeshFormat { kPly, kObj, kGlb };

// From the extension (.ply / .obj / .glb, any case); throws vf::Error naming the path otherwise.
MeshFormat meshFormatFromPath(const std::string& path);

struct MeshWriteOptions {
  bool with_class_property = false;  // PLY: an `int class` vertex property (needs mesh.classes)
  const ClassTable* classes = nullptr;  // OBJ/GLB: group/material names and colors per class
};

// Writes by extension. A mesh without triangles is written as a point cloud (PLY only).
void writeMesh(const TriangleMesh& mesh, const std::string& path, const MeshWriteOptions& options = {});

void writePly(const TriangleMesh& mesh, const std::string& path, bool with_class_property);
void writeObj(const TriangleMesh& mesh, const std::string& path, const ClassTable* classes);
void writeGlb(const TriangleMesh& mesh, const std::string& path, const ClassTable* classes);

// Reads a PLY (binary little endian or ASCII) with x y z and optional nx ny nz, red green blue,
// class; polygon faces are fanned into triangles. Throws vf::Error naming the file.
TriangleMesh readPly(const std::string& path);

}  // namespace vf
