// vdbfuse mesh: the scene's surface as PLY / OBJ / GLB, optionally filtered or split by class.
#include <chrono>
#include <cstdio>
#include <filesystem>
#include <memory>
#include <string>
#include <vector>

#include "app/command_registry.h"
#include "app/scene_axes.h"
#include "core/error.h"
#include "io/mesh_io.h"
#include "vdb/class_selection.h"
#include "vdb/mesh_ops.h"
#include "vdb/mesher.h"
#include "vdb/scene.h"

namespace vf::app {
namespace {

struct MeshCommandOptions {
  std::string scene, output, color = "rgb", axes;
  float min_weight = 0;
  std::vector<std::string> include, exclude;
  bool per_class = false, with_class_property = false;
  size_t min_component = 0;
};

double secondsSince(std::chrono::steady_clock::time_point t0) {
  return std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count();
}

void runMesh(const MeshCommandOptions& o) {
  const auto t0 = std::chrono::steady_clock::now();
  if (!o.include.empty() && !o.exclude.empty())
    throw Error("--include-classes and --exclude-classes cannot be combined");
  const SceneAxes axes = axesFor(o.axes, meshFormatFromPath(o.output));  // bad values fail before the work
  Scene scene = readScene(o.scene);
  MeshOptions options;
  options.min_weight = o.min_weight;
  options.color = o.color == "class" ? MeshColorMode::kClass : MeshColorMode::kRgb;
  if (options.color == MeshColorMode::kClass && !scene.hasClasses())
    throw Error("--color class: the scene has no class grid (fused without labels)");
  // Resolve class names before the work so that a typo fails at once.
  const bool include = !o.include.empty(), filter = include || !o.exclude.empty();
  std::set<int> ids;
  if (filter)
    ids = resolveClassSelection(scene.meta.classes, include ? o.include : o.exclude,
                                include ? "--include-classes" : "--exclude-classes");
  TriangleMesh mesh = meshScene(scene, options);
  std::printf("meshed %zu triangles, %zu vertices (min weight %.1f)\n", mesh.triangleCount(), mesh.vertexCount(),
              o.min_weight);
  if (filter) {
    const size_t before = mesh.triangleCount();
    mesh = filterFacesByClass(mesh, ids, include);
    std::printf("%s %s: %zu triangles removed\n", include ? "kept only" : "excluded",
                classNames(scene.meta.classes, ids).c_str(), before - mesh.triangleCount());
  }
  if (o.min_component > 1) {
    const ComponentStats before = meshComponents(mesh, o.min_component);
    const size_t removed = removeSmallComponents(mesh, o.min_component);
    std::printf("removed %zu triangles in %zu of %zu pieces (those under %zu triangles)\n", removed, before.small,
                before.pieces, o.min_component);
  }
  if (mesh.triangles.empty()) throw Error(o.output + ": nothing left to write (empty mesh)");
  transformMesh(mesh, exportRotationFor(scene, o.scene, axes));
  std::printf("axes %s (up from %s)\n", sceneAxesName(axes),
              axes == SceneAxes::kCamera ? "-" : scene.meta.up_source.c_str());
  MeshWriteOptions write;
  write.classes = &scene.meta.classes;
  write.with_class_property = o.with_class_property;
  write.class_colors = options.color == MeshColorMode::kClass;
  if (!o.per_class) {
    writeMesh(mesh, o.output, write);
    std::printf("wrote %s: %zu triangles (%.2f s)\n", o.output.c_str(), mesh.triangleCount(), secondsSince(t0));
    return;
  }
  if (!scene.hasClasses()) throw Error("--per-class: the scene has no class grid (fused without labels)");
  namespace fs = std::filesystem;
  const fs::path out(o.output);
  for (const auto& [id, part] : splitByClass(mesh)) {
    fs::path path = out.parent_path() / (out.stem().string() + "_" + classFileStem(scene.meta.classes, id) +
                                         out.extension().string());
    writeMesh(part, path.string(), write);
    std::printf("wrote %s: %zu triangles\n", path.string().c_str(), part.triangleCount());
  }
  std::printf("done (%.2f s)\n", secondsSince(t0));
}

void setup(CLI::App& root) {
  auto o = std::make_shared<MeshCommandOptions>();
  CLI::App* cmd = root.add_subcommand("mesh", "Extract the surface of a scene (marching cubes) to .ply, .obj or .glb");
  cmd->add_option("scene", o->scene, "scene document (.vdb)")->required();
  cmd->add_option("-o,--output", o->output, "output mesh; the extension picks the format (.ply/.obj/.glb)")->required();
  cmd->add_option("--min-weight", o->min_weight, "treat voxels observed fewer times as unobserved")->capture_default_str();
  cmd->add_option("--include-classes", o->include, "keep only faces of these classes (names or ids)")->delimiter(',');
  cmd->add_option("--exclude-classes", o->exclude, "drop faces of these classes (names or ids)")->delimiter(',');
  cmd->add_flag("--per-class", o->per_class, "write one mesh per class: <output stem>_<class>.<ext>");
  cmd->add_option("--min-component", o->min_component, "drop connected pieces (faces sharing a vertex) with fewer triangles");
  cmd->add_option("--color", o->color, "vertex colors: fused rgb or class colors")
      ->check(CLI::IsMember({"rgb", "class"}))
      ->capture_default_str();
  cmd->add_flag("--with-class-property", o->with_class_property, "PLY: add an int `class` vertex property");
  cmd->add_option("--axes", o->axes, kAxesHelp)->check(CLI::IsMember({"camera", "z-up", "y-up"}));
  cmd->callback([o] { runMesh(*o); });
}

}  // namespace

VF_REGISTER_COMMAND(20, setup);

}  // namespace vf::app
