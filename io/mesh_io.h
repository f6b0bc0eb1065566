#pragma once
// Mesh and point-cloud files: PLY (binary little endian, own code, with optional per-vertex
// class property), OBJ (one group + material per class) and GLB (through Assimp).
// Every writer goes through a temp file in the target directory renamed into place.
// Colours: the mesh holds sRGB bytes. PLY and OBJ vertex colours stay sRGB (what Blender's
// importers expect); glTF's COLOR_0 and every material colour (GLB base colour, OBJ Kd) are
// linear. Positions are written as given: the caller rotates into the file's frame
// (vdb/scene_frame.h).
#include <optional>
#include <string>

#include "core/class_table.h"
#include "core/mesh.h"

namespace vf {

enum class MeshFormat { kPly, kObj, kGlb };

// The frame a file's positions are in, against the scene's (the frame of the trajectory it was
// fused with). A PLY records it in a header comment, so that what compares the file with that
// trajectory or with ground truth (vdbfuse evaluate --mesh, vdbfuse-synth-room --evaluate) can
// bring a z-up or y-up export back rather than score it misplaced.
struct MeshFrame {
  std::string axes;  // "camera" (the scene's own), "z-up" or "y-up"
  Rigid3f file_from_scene = Rigid3f::identity();
};

// From the extension (.ply / .obj / .glb, any case); throws vf::Error naming the path otherwise.
MeshFormat meshFormatFromPath(const std::string& path);

// An encoded texture image that the mesh's uvs index (mesh.uvs): JPEG or PNG file bytes.
struct MeshTexture {
  std::string encoded;
  std::string extension;  // "jpg" or "png"
  // OBJ: name this image file (beside the OBJ, written by the caller once for several meshes)
  // instead of writing <stem>.<extension>.
  std::string shared_file;
};

struct MeshWriteOptions {
  bool with_class_property = false;  // PLY: an `int class` vertex property (needs mesh.classes)
  const ClassTable* classes = nullptr;  // OBJ/GLB: group/material names and colors per class
  // The mesh's colours are its class colours (the user asked for class colouring): OBJ/GLB then
  // colour each class's material with it. Otherwise vertex colours carry the look and a
  // material carries no class colour: GLB white, OBJ the group's mean colour (Kd is all that
  // Blender's OBJ importer wires into the material).
  bool class_colors = false;
  std::optional<MeshFrame> frame;  // PLY: recorded in the header
  // OBJ/GLB, with mesh.uvs: the base colour texture (GLB: embedded; OBJ: written beside it as
  // <stem>.<extension>, named by map_Kd). Vertex colours are then left out (glTF multiplies
  // COLOR_0 into the texture) and materials are white.
  const MeshTexture* texture = nullptr;
};

// The image file an OBJ with `texture` is written with: <path's stem>.<extension>.
std::string objTexturePath(const std::string& obj_path, const MeshTexture& texture);

// Writes by extension. A mesh without triangles is written as a point cloud (PLY only).
void writeMesh(const TriangleMesh& mesh, const std::string& path, const MeshWriteOptions& options = {});

void writePly(const TriangleMesh& mesh, const std::string& path, bool with_class_property,
              const std::optional<MeshFrame>& frame = std::nullopt);
void writeObj(const TriangleMesh& mesh, const std::string& path, const MeshWriteOptions& options = {});
void writeGlb(const TriangleMesh& mesh, const std::string& path, const MeshWriteOptions& options = {});

// Reads a PLY (binary little endian or ASCII) with x y z and optional nx ny nz, red green blue,
// class; polygon faces are fanned into triangles. Throws vf::Error naming the file. `frame`,
// when given, receives the frame the header records (nullopt: none, as in other tools' files).
TriangleMesh readPly(const std::string& path, std::optional<MeshFrame>* frame = nullptr);

// readPly, then a file vdbfuse wrote in another frame (mesh/export --axes z-up or y-up) moved
// back into the scene's frame, the trajectory's: what a comparison with ground truth needs.
// `note` says which ("as written", or "written --axes z-up, brought back into the scene's frame").
TriangleMesh readPlyInSceneFrame(const std::string& path, std::string* note = nullptr);

}  // namespace vf
