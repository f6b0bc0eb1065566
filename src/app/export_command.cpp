// vdbfuse export: a Blender-ready folder (per-class meshes + fog volume) or a point cloud.
#include <cstdio>
#include <filesystem>
#include <fstream>
#include <cstdint>
#include <map>
#include <memory>
#include <vector>
#include <string>

#include "app/command_registry.h"
#include "app/output_policy.h"
#include "app/scene_axes.h"
#include "app/texture_export.h"
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
  std::string scene, output, color = "rgb", axes;
  bool blender = false, points = false, force = false;
  float min_weight = 0;
  TextureCliOptions texture;
};

std::string jsonEscape(const std::string& s) {
  std::string out;
  for (char c : s) {
    if (c == '"' || c == '\\') out += '\\';
    out += c;
  }
  return out;
}

std::string jsonVec(Vec3f v) {
  char text[96];
  std::snprintf(text, sizeof text, "[%.6g, %.6g, %.6g]", v.x, v.y, v.z);
  return text;
}

// a * b: b first, then a.
Rigid3f composeRigid(const Rigid3f& a, const Rigid3f& b) {
  Rigid3f out;
  for (int i = 0; i < 3; ++i)
    for (int j = 0; j < 3; ++j)
      out.r[i * 3 + j] = a.r[i * 3] * b.r[j] + a.r[i * 3 + 1] * b.r[3 + j] + a.r[i * 3 + 2] * b.r[6 + j];
  out.t = a * b.t;
  return out;
}

void exportBlender(Scene& scene, const ExportOptions& o) {
  const SceneAxes axes = axesFor(o.axes, MeshFormat::kPly);
  const Rigid3f to_file = exportRotationFor(scene, o.scene, axes);
  // Textured meshes go as OBJ, which Blender's importer turns from Y-up into its Z-up: written
  // y-up, they land where the z-up volume and PLYs do.
  if (o.texture.texture && axes != SceneAxes::kZUp)
    throw Error("--texture in a Blender folder: the OBJ meshes need the default --axes z-up");
  const Rigid3f obj_from_file = o.texture.texture
                                    ? composeRigid(exportRotationFor(scene, o.scene, SceneAxes::kYUp), to_file.inverse())
                                    : Rigid3f::identity();
  // Written whole into a temporary folder beside the output, which replaces the old one at the end.
  AtomicFolder folder(o.output);
  MeshOptions options;
  options.min_weight = o.min_weight;
  TriangleMesh mesh = meshScene(scene, options);
  simplifyIfAsked(mesh, o.texture);
  // Textured: one atlas for the whole surface, baked in the scene's frame; each class's mesh is
  // an OBJ naming the one texture image.
  TexturedMesh textured;
  if (o.texture.texture) {
    textured = bakeTexturedMesh(scene, o.scene, mesh, {}, o.texture);
    mesh = std::move(textured.mesh);
    textured.texture.shared_file = "texture." + textured.texture.extension;
    writeFileAtomic(folder.file(textured.texture.shared_file), textured.texture.encoded);
  }
  transformMesh(mesh, to_file);
  Vec3f lo{0, 0, 0}, hi{0, 0, 0};
  for (size_t i = 0; i < mesh.positions.size(); ++i) {
    const Vec3f& p = mesh.positions[i];
    lo = i ? Vec3f{std::min(lo.x, p.x), std::min(lo.y, p.y), std::min(lo.z, p.z)} : p;
    hi = i ? Vec3f{std::max(hi.x, p.x), std::max(hi.y, p.y), std::max(hi.z, p.z)} : p;
  }
  // Manifest for samples/blender/import_scene.py: one object per class, plus the volume.
  std::string manifest = "{\n  \"meshes\": [\n";
  bool first = true;
  std::string report;
  std::map<int32_t, TriangleMesh> parts = splitByClass(mesh);
  mesh = TriangleMesh();  // the parts hold it now; the volume below needs the memory
  std::vector<int32_t> ids;
  for (const auto& [id, part] : parts) ids.push_back(id);
  const std::map<int32_t, std::string> stems = uniqueClassFileStems(scene.meta.classes, ids);
  for (const auto& [id, part] : parts) {
    const std::string stem = scene.hasClasses() ? stems.at(id) : "surface";
    const std::string file = stem + (o.texture.texture ? ".obj" : ".ply");
    if (o.texture.texture) {
      MeshWriteOptions write;
      write.texture = &textured.texture;
      TriangleMesh y_up = part;
      transformMesh(y_up, obj_from_file);
      writeObj(y_up, folder.file(file), write);  // its .mtl beside it, naming the texture
    } else {
      writePly(part, folder.file(file), false, MeshFrame{sceneAxesName(axes), to_file});
    }
    const ClassInfo* info = scene.meta.classes.findId(id);
    const Rgb8 c = classColorOf(scene.meta.classes, id);
    manifest += std::string(first ? "" : ",\n") + "    {\"file\": \"" + jsonEscape(file) + "\", \"class_id\": " +
                std::to_string(id) + ", \"name\": \"" + jsonEscape(info ? info->name : stem) +
                "\", \"class_color\": [" + std::to_string(c.r) + ", " + std::to_string(c.g) + ", " +
                std::to_string(c.b) + "], \"triangles\": " + std::to_string(part.triangleCount()) + "}";
    first = false;
    report += "wrote " + file + ": " + std::to_string(part.triangleCount()) + " triangles\n";
  }
  parts.clear();
  const BlenderVolumeInfo volume = writeBlenderVolume(scene, folder.file("volume.vdb"), to_file);
  char volume_line[160];
  std::snprintf(volume_line, sizeof volume_line,
                "wrote volume.vdb: density + color grids (density %.3g..%.3g over a %.3f m band)\n",
                volume.density_min, volume.density_max, volume.band_m);
  report += volume_line;
  const SceneMetadata& m = scene.meta;
  char numbers[256];
  std::snprintf(numbers, sizeof numbers,
                "  \"voxel_size_m\": %.6g,\n  \"density_range\": [%.6g, %.6g],\n  \"density_band_m\": %.6g,\n",
                m.voxel_size_m, volume.density_min, volume.density_max, volume.band_m);
  manifest += "\n  ],\n  \"volume\": \"volume.vdb\",\n" + std::string(numbers);
  if (o.texture.texture)
    manifest += "  \"texture\": \"" + jsonEscape(textured.texture.shared_file) + "\",\n  \"texture_px\": " +
                std::to_string(textured.page_px) + ",\n";
  // How the files map back to the scene: p_file = rotation * p_scene (rows).
  manifest += "  \"axes\": \"" + std::string(sceneAxesName(axes)) + "\",\n  \"up_source\": \"" +
              jsonEscape(axes == SceneAxes::kCamera ? "" : m.up_source) + "\",\n  \"rotation\": [" +
              jsonVec({to_file.r[0], to_file.r[1], to_file.r[2]}) + ", " + jsonVec({to_file.r[3], to_file.r[4], to_file.r[5]}) +
              ", " + jsonVec({to_file.r[6], to_file.r[7], to_file.r[8]}) + "],\n  \"bounds_min\": " + jsonVec(lo) +
              ",\n  \"bounds_max\": " + jsonVec(hi) + "\n}\n";
  // Temp file + rename, with write errors reported (an unchecked ofstream renamed a short file).
  writeFileAtomic(folder.file("scene.json"), manifest);
  folder.commit();
  std::printf("%s", report.c_str());  // only now is any of it written
  std::printf("axes %s (up from %s)\n", sceneAxesName(axes), axes == SceneAxes::kCamera ? "-" : m.up_source.c_str());
  std::printf("wrote scene.json; import with: blender --python samples/blender/import_scene.py -- %s\n",
              o.output.c_str());
}

// Messages name the folder the user asked for, not the temporary one being filled.
void exportBlenderNamingTarget(Scene& scene, const ExportOptions& o) {
  try {
    exportBlender(scene, o);
  } catch (const Error& e) {
    throw Error("cannot write " + o.output + " (the old folder, if any, is kept): " + e.what());
  }
}

void runExport(const ExportOptions& o) {
  if (o.blender == o.points) throw Error("export: choose exactly one of --blender and --points");
  checkTextureOptions(o.texture);
  if (!o.blender && (o.texture.texture || o.texture.target_triangles > 0))
    throw Error("--texture and --target-triangles go with --blender (a point cloud has no triangles)");
  if (!o.axes.empty()) parseSceneAxes(o.axes);
  OutputPolicy outputs(o.force);
  outputs.input(o.scene);
  if (o.blender) {
    outputs.folder(o.output, "-o");
  } else {
    OutputPolicy::requireExtension(o.output, {".ply"}, "-o");
    outputs.file(o.output, "-o");
  }
  Scene scene = readScene(o.scene);
  if (o.color == "class" && !scene.hasClasses())
    throw Error("--color class: the scene has no class grid (fused without labels)");
  if (o.blender) return exportBlenderNamingTarget(scene, o);
  MeshOptions options;
  options.min_weight = o.min_weight;
  options.color = o.color == "class" ? MeshColorMode::kClass : MeshColorMode::kRgb;
  TriangleMesh cloud = scenePointCloud(scene, options);
  const SceneAxes axes = axesFor(o.axes, MeshFormat::kPly);
  const Rigid3f to_file = exportRotationFor(scene, o.scene, axes);
  transformMesh(cloud, to_file);
  writePly(cloud, o.output, cloud.hasClasses(), MeshFrame{sceneAxesName(axes), to_file});
  std::printf("wrote %s: %zu points\n", o.output.c_str(), cloud.vertexCount());
}

void setupExportCommand(CLI::App& root) {
  auto o = std::make_shared<ExportOptions>();
  CLI::App* cmd = root.add_subcommand("export", "Export a scene for Blender (meshes + volume) or as a point cloud");
  cmd->add_option("scene", o->scene, "scene document (.vdb)")->required();
  cmd->add_option("-o,--output", o->output, "--blender: output folder; --points: output .ply")->required();
  cmd->add_flag("--blender", o->blender, "per-class PLY meshes, volume.vdb (density, color) and scene.json");
  cmd->add_flag("-f,--force", o->force, "overwrite an existing output (--blender: replace the folder and all in it)");
  cmd->add_flag("--points", o->points, "surface points (zero crossings) with colors as PLY");
  cmd->add_option("--color", o->color, "--points colors: fused rgb or class colors")
      ->check(CLI::IsMember({"rgb", "class"}))
      ->capture_default_str();
  cmd->add_option("--min-weight", o->min_weight, "treat voxels observed fewer times as unobserved");
  cmd->add_option("--axes", o->axes, "frame of the files: camera (as fused), z-up (default: Blender, PLY) or y-up")
      ->check(CLI::IsMember({"camera", "z-up", "y-up"}));
  addSimplifyOptions(*cmd, o->texture);
  addTextureOptions(*cmd, o->texture);
  cmd->callback([o] { runExport(*o); });
}

}  // namespace

VF_REGISTER_COMMAND(40, setupExportCommand);

}  // namespace vf::app
