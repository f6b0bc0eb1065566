// vdbfuse export: a Blender-ready folder (per-class meshes + fog volume) or a point cloud.
#include <cstdio>
#include <filesystem>
#include <fstream>
#include <memory>
#include <string>

#include "app/command_registry.h"
#include "core/error.h"
#include "core/atomic_output.h"
#include "io/image_io.h"
#include "io/mesh_io.h"
#include "vdb/mesh_ops.h"
#include "vdb/mesher.h"
#include "vdb/scene.h"
#include "vdb/scene_export.h"

namespace vf::app {
namespace {

namespace fs = std::filesystem;

struct ExportOptions {
  std::string scene, output, color = "rgb";
  bool blender = false, points = false;
  float min_weight = 0;
};

std::string jsonEscape(const std::string& s) {
  std::string out;
  for (char c : s) {
    if (c == '"' || c == '\\') out += '\\';
    out += c;
  }
  return out;
}

void exportBlender(const Scene& scene, const ExportOptions& o) {
  fs::create_directories(o.output);
  MeshOptions options;
  options.min_weight = o.min_weight;
  const TriangleMesh mesh = meshScene(scene, options);
  // Manifest for samples/blender/import_scene.py: one object per class, plus the volume.
  std::string manifest = "{\n  \"meshes\": [\n";
  bool first = true;
  for (const auto& [id, part] : splitByClass(mesh)) {
    const std::string stem = scene.hasClasses() ? classFileStem(scene.meta.classes, id) : "surface";
    const std::string file = stem + ".ply";
    writePly(part, (fs::path(o.output) / file).string(), false);
    const ClassInfo* info = scene.meta.classes.findId(id);
    const Rgb8 c = info ? info->color : Rgb8{200, 200, 200, 255};
    manifest += std::string(first ? "" : ",\n") + "    {\"file\": \"" + jsonEscape(file) + "\", \"class_id\": " +
                std::to_string(id) + ", \"name\": \"" + jsonEscape(info ? info->name : stem) +
                "\", \"class_color\": [" + std::to_string(c.r) + ", " + std::to_string(c.g) + ", " +
                std::to_string(c.b) + "]}";
    first = false;
    std::printf("wrote %s: %zu triangles\n", file.c_str(), part.triangleCount());
  }
  writeBlenderVolume(scene, (fs::path(o.output) / "volume.vdb").string());
  std::printf("wrote volume.vdb: density + color grids\n");
  manifest += "\n  ],\n  \"volume\": \"volume.vdb\",\n  \"voxel_size_m\": " + std::to_string(scene.meta.voxel_size_m) +
              "\n}\n";
  // Temp file + rename, with write errors reported (an unchecked ofstream renamed a short file).
  writeFileAtomic((fs::path(o.output) / "scene.json").string(), manifest);
  std::printf("wrote scene.json; import with: blender --python samples/blender/import_scene.py -- %s\n",
              o.output.c_str());
}

void runExport(const ExportOptions& o) {
  if (o.blender == o.points) throw Error("export: choose exactly one of --blender and --points");
  const Scene scene = readScene(o.scene);
  if (o.color == "class" && !scene.hasClasses())
    throw Error("--color class: the scene has no class grid (fused without labels)");
  if (o.blender) return exportBlender(scene, o);
  if (meshFormatFromPath(o.output) != MeshFormat::kPly) throw Error(o.output + ": --points writes .ply only");
  MeshOptions options;
  options.min_weight = o.min_weight;
  options.color = o.color == "class" ? MeshColorMode::kClass : MeshColorMode::kRgb;
  const TriangleMesh cloud = scenePointCloud(scene, options);
  writePly(cloud, o.output, cloud.hasClasses());
  std::printf("wrote %s: %zu points\n", o.output.c_str(), cloud.vertexCount());
}

void setup(CLI::App& root) {
  auto o = std::make_shared<ExportOptions>();
  CLI::App* cmd = root.add_subcommand("export", "Export a scene for Blender (meshes + volume) or as a point cloud");
  cmd->add_option("scene", o->scene, "scene document (.vdb)")->required();
  cmd->add_option("-o,--output", o->output, "--blender: output folder; --points: output .ply")->required();
  cmd->add_flag("--blender", o->blender, "per-class PLY meshes, volume.vdb (density, color) and scene.json");
  cmd->add_flag("--points", o->points, "surface points (zero crossings) with colors as PLY");
  cmd->add_option("--color", o->color, "--points colors: fused rgb or class colors")
      ->check(CLI::IsMember({"rgb", "class"}))
      ->capture_default_str();
  cmd->add_option("--min-weight", o->min_weight, "treat voxels observed fewer times as unobserved");
  cmd->callback([o] { runExport(*o); });
}

}  // namespace

VF_REGISTER_COMMAND(40, setup);

}  // namespace vf::app
