// vdbfuse edit: class removal, crop, outlier removal and smoothing on a scene document,
// written to a new file (the input is never modified). The trajectory beside the input
// (scene.vdb -> scene.txt) is copied beside the output: edits keep the frame, so it still fits.
#include <cstdio>
#include <filesystem>
#include <memory>
#include <string>
#include <vector>

#include "app/command_registry.h"
#include "app/usage_errors.h"
#include "app/output_policy.h"
#include "app/scene_axes.h"
#include "core/atomic_output.h"
#include "core/error.h"
#include "core/mapped_file.h"
#include "io/image_io.h"
#include "vdb/class_selection.h"
#include "vdb/scene.h"
#include "vdb/scene_edit.h"

namespace vf::app {
namespace {

struct EditOptions {
  std::string scene, output;
  std::vector<std::string> exclude;
  std::vector<float> crop_box;
  std::string crop_axes = "camera";
  bool remove_outliers = false, force = false;
  size_t min_component = 500;
  float outlier_min_weight = 2;
  int smooth = 0;
};

void runEdit(const EditOptions& o) {
  namespace fs = std::filesystem;
  OutputPolicy::requireExtension(o.output, {".vdb"}, "-o");
  // A bad box fails before the scene is read.
  const std::vector<float>& b = o.crop_box;
  if (!b.empty() && b.size() != 6) throw Error("--crop-box needs six numbers: xmin,ymin,zmin,xmax,ymax,zmax (metres)");
  if (!b.empty() && !(b[0] < b[3] && b[1] < b[4] && b[2] < b[5]))
    throw Error("--crop-box: need xmin < xmax, ymin < ymax and zmin < zmax (the first three numbers are the minimum)");
  const std::string trajectory_in = fs::path(o.scene).replace_extension(".txt").string();
  const std::string trajectory_out = fs::path(o.output).replace_extension(".txt").string();
  std::error_code ec;
  const bool copy_trajectory = fs::exists(trajectory_in, ec);
  OutputPolicy outputs(o.force);
  outputs.input(o.scene);
  if (copy_trajectory) outputs.input(trajectory_in);
  outputs.file(o.output, "-o");
  if (copy_trajectory) outputs.file(trajectory_out, "the trajectory copied beside -o");
  // Copied byte for byte: edits keep the frame.
  const std::string trajectory =
      copy_trajectory ? readRegularFile(trajectory_in, "trajectory beside the scene", kMaxTextFileBytes) : "";
  Scene scene = readScene(o.scene);
  const size_t before = scene.activeVoxelCount();
  std::printf("read %s: %zu active voxels\n", o.scene.c_str(), before);
  if (!o.exclude.empty()) {
    const std::set<int> ids = resolveClassSelection(scene.meta.classes, o.exclude, "--exclude-classes");
    const size_t n = excludeClassVoxels(scene, ids);
    std::printf("exclude-classes %s: removed %zu voxels\n", classNames(scene.meta.classes, ids).c_str(), n);
  }
  if (!o.crop_box.empty()) {
    const SceneAxes axes = parseSceneAxes(o.crop_axes);
    const Rigid3f box_from_scene = exportRotationFor(scene, o.scene, axes);
    const size_t n = cropToBox(scene, {b[0], b[1], b[2]}, {b[3], b[4], b[5]}, box_from_scene);
    std::printf("crop-box (%s axes%s): removed %zu voxels outside the box\n", sceneAxesName(axes),
                axes == SceneAxes::kCamera ? ", the scene's own" : ", as the exports", n);
  }
  if (o.remove_outliers) {
    OutlierOptions options;
    options.min_weight = o.outlier_min_weight;
    options.min_component_triangles = o.min_component;
    const OutlierReport r = removeOutliers(scene, options);
    std::printf("remove-outliers: removed %zu voxels observed fewer than %.1f times\n", r.weak_voxels,
                o.outlier_min_weight);
    std::printf("remove-outliers: surface pieces under %zu triangles: %zu of %zu before, %zu of %zu after "
                "(%zu voxels removed in %d passes, and %zu voxels of band left without a surface)\n",
                o.min_component, r.small_pieces_before, r.pieces_before, r.small_pieces_after, r.pieces_after,
                r.piece_voxels, r.passes, r.bare_band_voxels);
    if (r.small_pieces_after > 0)
      std::printf("remove-outliers: note: %zu small pieces remain after %d passes\n", r.small_pieces_after, r.passes);
  }
  if (o.smooth > 0) {
    const size_t n = smoothScene(scene, o.smooth);
    std::printf("smooth %d: changed %zu voxel values\n", o.smooth, n);
  }
  if (scene.activeVoxelCount() == 0) throw Error("the edits removed every voxel; nothing written");
  writeScene(scene, o.output);
  if (copy_trajectory) writeFileAtomic(trajectory_out, trajectory);
  std::printf("wrote %s: %zu active voxels (%zu removed)%s\n", o.output.c_str(), scene.activeVoxelCount(),
              before - scene.activeVoxelCount(), copy_trajectory ? (" and " + trajectory_out).c_str() : "");
}

void setupEditCommand(CLI::App& root) {
  auto o = std::make_shared<EditOptions>();
  CLI::App* cmd = root.add_subcommand("edit", "Remove classes, crop, drop outliers or smooth a scene into a new .vdb");
  cmd->add_option("scene", o->scene, "input scene (.vdb), never modified")->required()->check(existingFile());
  cmd->add_option("-o,--output", o->output, "output scene (.vdb)")->required();
  cmd->add_flag("-f,--force", o->force, "overwrite an existing output");
  cmd->add_option("--exclude-classes", o->exclude, "remove the voxels of these classes (names or ids)")->delimiter(',');
  cmd->add_option("--crop-box", o->crop_box, "keep voxels inside xmin,ymin,zmin,xmax,ymax,zmax (metres)")
      ->delimiter(',');
  cmd->add_option("--crop-axes", o->crop_axes,
                  "frame of --crop-box: camera (the scene's, as `info` prints bounds), z-up (a PLY export in "
                  "Blender) or y-up (OBJ / GLB files)")
      ->check(CLI::IsMember({"camera", "z-up", "y-up"}))
      ->capture_default_str();
  cmd->add_flag("--remove-outliers", o->remove_outliers,
                "drop voxels observed fewer than --outlier-min-weight times, then the surface pieces under "
                "--min-component triangles (the pieces `mesh --min-component` drops), so none is left");
  cmd->add_option("--min-component", o->min_component,
                  "with --remove-outliers: smallest surface piece kept, in triangles")
      ->capture_default_str()
      ->check(atLeast(0));
  cmd->add_option("--outlier-min-weight", o->outlier_min_weight, "with --remove-outliers: least observations kept")
      ->capture_default_str()
      ->check(atLeast(0));
  cmd->add_option("--smooth", o->smooth, "iterations of level-set mean-curvature smoothing")->check(inRange(0, 100));
  cmd->callback([o] { runEdit(*o); });
}

}  // namespace

VF_REGISTER_COMMAND(35, setupEditCommand);

}  // namespace vf::app
