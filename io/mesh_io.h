#pragma once
// Mesh and point-cloud files: PLY (binary little endian, own code, with optional per-vertex
// class property), OBJ (one group + material per class) and GLB (through Assimp).
// Every writer goes through a temp file in the target directory renamed into place.
// Colours: the mesh holds sRGB bytes. PLY and OBJ vertex colours stay sRGB (what Blender's
// importers expect); glTF's COLOR_0 and every material colour (GLB base colour, OBJ Kd) are
// linear. Positions are written as given: the caller rotates into the file's frame
// (vdb/scene_frame.h).
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
  // The mesh's colours are its class colours (the user asked for class colouring): OBJ/GLB then
  // colour each class's material with it. Otherwise vertex colours carry the look and a
  // material carries no class colour: GLB white, OBJ the group's mean colour (Kd is all that
  // Blender's OBJ importer wires into the material).
  bool class_colors = false;
};

// Writes by extension. A mesh without triangles is written as a point cloud (PLY only).
void writeMesh(const TriangleMesh& mesh, const std::string& path, const MeshWriteOptions& options = {});

void writePly(const TriangleMesh& mesh, const std::string& path, bool with_class_property);
void writeObj(const TriangleMesh& mesh, const std::string& path, const MeshWriteOptions& options = {});
void writeGlb(const TriangleMesh& mesh, const std::string& path, const MeshWriteOptions& options = {});

// Reads a PLY (binary little endian or ASCII) with x y z and optional nx ny nz, red green blue,
// class; polygon faces are fanned into triangles. Throws vf::Error naming the file.
TriangleMesh readPly(const std::string& path);

}  // namespace vf
