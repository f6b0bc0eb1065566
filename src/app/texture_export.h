#pragma once
// The options `mesh` and `export --blender` share for light, textured meshes, and the steps
// behind them: simplification (texture/mesh_simplify.h), the UV atlas (texture/uv_atlas.h) and
// the bake from the scene's frames (app/bake_frames.h, texture/texture_bake.h).
#include <CLI/CLI.hpp>

#include <cstdint>
#include <set>
#include <string>

#include "app/bake_frames.h"
#include "core/mesh.h"
#include "io/mesh_io.h"
#include "vdb/scene.h"

namespace vf::app {

struct TextureCliOptions {
  int64_t target_triangles = 0;  // 0: keep every marching-cubes triangle
  float max_error_mm = 20.f;
  bool texture = false;
  float texel_mm = 2.f;
  int max_texture_px = 8192;
  std::string image_format = "jpg";
  int jpeg_quality = 90;
  BakeFrameOptions frames;
};

// --target-triangles, --max-error-mm.
void addSimplifyOptions(CLI::App& cmd, TextureCliOptions& o);
// --texture and the bake's options (--texel-mm, --texture-size, --texture-format, --frames,
// --trajectory, --labels, --bake-max-frames).
void addTextureOptions(CLI::App& cmd, TextureCliOptions& o);
// Throws vf::Error for values out of range (before any work).
void checkTextureOptions(const TextureCliOptions& o);

// Simplifies when --target-triangles asks for fewer triangles than the mesh has; prints what it did.
void simplifyIfAsked(TriangleMesh& mesh, const TextureCliOptions& o);

struct TexturedMesh {
  TriangleMesh mesh;      // vertices split along chart borders, uvs set
  MeshTexture texture;    // the encoded page
  int page_px = 0;
};

// Atlas + bake of `mesh` (in the scene's frame), never painting `masked_classes` from a frame.
// Prints the steps and their times.
TexturedMesh bakeTexturedMesh(const Scene& scene, const std::string& scene_path, const TriangleMesh& mesh,
                              const std::set<int>& masked_classes, const TextureCliOptions& o);

}  // namespace vf::app
