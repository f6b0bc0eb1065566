// Fuzz target: a PLY mesh as `vdbfuse evaluate --mesh` reads it (binary or ASCII, the vdbfuse
// frame comment included), opened from a temp file.
#include <cmath>

#include "core/error.h"
#include "fuzz/fuzz_util.h"
#include "io/mesh_io.h"

extern "C" int LLVMFuzzerTestOneInput(const uint8_t* data, size_t size) {
  const std::string path = vf::fuzz::writeTempInput("_mesh.ply", data, size);
  try {
    std::optional<vf::MeshFrame> frame;
    vf::TriangleMesh mesh = vf::readPly(path, &frame);
    // Documented: every face index names a vertex; per-vertex arrays are empty or full.
    for (const auto& t : mesh.triangles)
      for (int32_t v : t)
        if (v < 0 || size_t(v) >= mesh.positions.size()) std::abort();
    if (mesh.hasNormals() && mesh.normals.size() != mesh.positions.size()) std::abort();
    if (mesh.hasColors() && mesh.colors.size() != mesh.positions.size()) std::abort();
    if (frame) {
      for (float r : frame->file_from_scene.r)
        if (!std::isfinite(r)) std::abort();
      const vf::TriangleMesh back = vf::readPlyInSceneFrame(path);
      if (back.positions.size() != mesh.positions.size()) std::abort();
    }
  } catch (const vf::Error&) {
  }
  return 0;
}
