// vdbfuse mesh: the scene's surface as PLY / OBJ / GLB, optionally filtered or split by class.
#include <chrono>
#include <cstdio>
#include <filesystem>
#include <cstdint>
#include <map>
#include <set>
#include <memory>
#include <string>
#include <vector>

#include "app/command_registry.h"
#include "app/output_policy.h"
#include "app/progress.h"
#include "app/scene_axes.h"
#include "app/texture_export.h"
#include "core/atomic_output.h"
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
  bool per_class = false, with_class_property = false, force = false;
  int64_t min_component = 0;
  TextureCliOptions texture;
};

namespace fs = std::filesystem;

// Claims `path` and, for OBJ, the material library (and texture image) written beside it.
void claimMeshFile(OutputPolicy& outputs, const std::string& path, const std::string& option,
                   const std::string& texture_extension = "") {
  outputs.file(path, option);
  if (meshFormatFromPath(path) == MeshFormat::kObj) {
    outputs.file(fs::path(path).replace_extension(".mtl").string(), option + " (its .mtl)");
    if (!texture_extension.empty())
      outputs.file(fs::path(path).replace_extension("." + texture_extension).string(), option + " (its texture)");
  }
}

// Removes the pieces of `mesh` under min_component triangles and says how many went.
void dropSmallPieces(TriangleMesh& mesh, size_t min_component, const std::string& prefix) {
  const ComponentStats before = meshComponents(mesh, min_component);
  const size_t removed = removeSmallComponents(mesh, min_component);
  std::printf("%sremoved %zu triangles in %zu of %zu pieces (those under %zu triangles)\n", prefix.c_str(), removed,
              before.small, before.pieces, min_component);
}

void runMesh(const MeshCommandOptions& o) {
  const auto t0 = std::chrono::steady_clock::now();
  if (!o.include.empty() && !o.exclude.empty())
    throw Error("--include-classes and --exclude-classes cannot be combined");
  if (o.min_component < 0) throw Error("--min-component " + std::to_string(o.min_component) + ": expected triangles >= 0");
  const SceneAxes axes = axesFor(o.axes, meshFormatFromPath(o.output));  // bad values fail before the work
  checkTextureOptions(o.texture);
  if (o.texture.texture && meshFormatFromPath(o.output) == MeshFormat::kPly)
    throw Error("--texture: PLY carries no texture; write .glb or .obj");
  if (o.texture.texture && o.per_class) throw Error("--texture and --per-class cannot be combined (one atlas per mesh)");
  if (o.texture.texture && o.color == "class") throw Error("--texture and --color class cannot be combined");
  OutputPolicy outputs(o.force);
  outputs.input(o.scene);
  if (!o.per_class) claimMeshFile(outputs, o.output, "-o", o.texture.texture ? o.texture.image_format : "");
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
  // --per-class counts the pieces of each class mesh, after the split: a piece of the whole
  // surface spans several classes, and its part in one class can be a sliver.
  if (o.min_component > 1 && !o.per_class) dropSmallPieces(mesh, size_t(o.min_component), "");
  if (mesh.triangles.empty()) throw Error(o.output + ": nothing left to write (empty mesh)");
  simplifyIfAsked(mesh, o.texture);
  // Baked in the scene's frame, where the frames' poses are; the uvs do not change when rotated.
  TexturedMesh textured;
  if (o.texture.texture) {
    textured = bakeTexturedMesh(scene, o.scene, mesh, include ? std::set<int>{} : ids, o.texture);
    mesh = std::move(textured.mesh);
  }
  const Rigid3f to_file = exportRotationFor(scene, o.scene, axes);
  transformMesh(mesh, to_file);
  std::printf("axes %s (up from %s)\n", sceneAxesName(axes),
              axes == SceneAxes::kCamera ? "-" : scene.meta.up_source.c_str());
  MeshWriteOptions write;
  write.classes = &scene.meta.classes;
  write.with_class_property = o.with_class_property;
  write.class_colors = options.color == MeshColorMode::kClass;
  write.frame = MeshFrame{sceneAxesName(axes), to_file};
  if (o.texture.texture) write.texture = &textured.texture;
  if (!o.per_class) {
    writeMesh(mesh, o.output, write);
    std::printf("wrote %s: %zu triangles (%.2f s)\n", o.output.c_str(), mesh.triangleCount(), secondsSince(t0));
    return;
  }
  if (!scene.hasClasses()) throw Error("--per-class: the scene has no class grid (fused without labels)");
  // All class meshes or none: they are written into a temporary folder beside the output and
  // moved into place together once every one is whole.
  const fs::path out(o.output);
  const fs::path folder = out.has_parent_path() ? out.parent_path() : fs::path(".");
  std::map<int32_t, TriangleMesh> parts = splitByClass(mesh);
  if (o.min_component > 1) {
    for (auto it = parts.begin(); it != parts.end();) {
      const ClassInfo* info = scene.meta.classes.findId(it->first);
      const std::string name = info ? info->name : "unknown";
      dropSmallPieces(it->second, size_t(o.min_component), name + ": ");
      if (it->second.triangles.empty()) {
        std::printf("%s: every piece is under %lld triangles; no mesh written\n", name.c_str(),
                    static_cast<long long>(o.min_component));
        it = parts.erase(it);
      } else {
        ++it;
      }
    }
    if (parts.empty()) throw Error(o.output + ": nothing left to write (every class mesh is under --min-component)");
  }
  std::vector<int32_t> part_ids;
  for (const auto& [id, part] : parts) part_ids.push_back(id);
  const std::map<int32_t, std::string> stems = uniqueClassFileStems(scene.meta.classes, part_ids);
  std::map<int32_t, std::string> names;
  for (const auto& [id, stem] : stems) {
    names[id] = out.stem().string() + "_" + stem + out.extension().string();
    claimMeshFile(outputs, (folder / names[id]).string(), "--per-class");
  }
  AtomicFolder staging((folder / (out.stem().string() + "_classes")).string());
  for (const auto& [id, part] : parts) {
    try {
      writeMesh(part, staging.file(names[id]), write);
    } catch (const Error& e) {
      throw Error("cannot write " + (folder / names[id]).string() + " (no class mesh was replaced): " + e.what());
    }
  }
  staging.commitFilesInto(folder.string());
  for (const auto& [id, part] : parts)
    std::printf("wrote %s: %zu triangles\n", (folder / names[id]).string().c_str(), part.triangleCount());
  std::printf("done (%.2f s)\n", secondsSince(t0));
}

void setupMeshCommand(CLI::App& root) {
  auto o = std::make_shared<MeshCommandOptions>();
  CLI::App* cmd = root.add_subcommand("mesh", "Extract the surface of a scene (marching cubes) to .ply, .obj or .glb");
  cmd->add_option("scene", o->scene, "scene document (.vdb)")->required();
  cmd->add_option("-o,--output", o->output, "output mesh; the extension picks the format (.ply/.obj/.glb)")->required();
  cmd->add_option("--min-weight", o->min_weight, "treat voxels observed fewer times as unobserved")->capture_default_str();
  cmd->add_option("--include-classes", o->include, "keep only faces of these classes (names or ids)")->delimiter(',');
  cmd->add_option("--exclude-classes", o->exclude, "drop faces of these classes (names or ids)")->delimiter(',');
  cmd->add_flag("--per-class", o->per_class, "write one mesh per class: <output stem>_<class>.<ext>");
  cmd->add_flag("-f,--force", o->force, "overwrite existing outputs");
  cmd->add_option("--min-component", o->min_component, "drop connected pieces (faces sharing a vertex) with fewer triangles");
  cmd->add_option("--color", o->color, "vertex colors: fused rgb or class colors")
      ->check(CLI::IsMember({"rgb", "class"}))
      ->capture_default_str();
  cmd->add_flag("--with-class-property", o->with_class_property, "PLY: add an int `class` vertex property");
  cmd->add_option("--axes", o->axes, kAxesHelp)->check(CLI::IsMember({"camera", "z-up", "y-up"}));
  addSimplifyOptions(*cmd, o->texture);
  addTextureOptions(*cmd, o->texture);
  cmd->callback([o] { runMesh(*o); });
}

}  // namespace

VF_REGISTER_COMMAND(20, setupMeshCommand);

}  // namespace vf::app
