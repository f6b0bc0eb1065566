// vdbfuse edit: class removal, crop, outlier removal and smoothing on a scene document,
// written to a new file (the input is never modified).
#include <cstdio>
#include <filesystem>
#include <memory>
#include <string>
#include <vector>

#include "app/command_registry.h"
#include "core/error.h"
#include "vdb/class_selection.h"
#include "vdb/scene.h"
#include "vdb/scene_edit.h"

namespace vf::app {
namespace {

struct EditOptions {
  std::string scene, output;
  std::vector<std::string> exclude;
  std::vector<float> crop_box;
  bool remove_outliers = false, force = false;
  size_t min_component_voxels = 500;
  float outlier_min_weight = 2;
  int smooth = 0;
};

void runEdit(const EditOptions& o) {
  namespace fs = std::filesystem;
  std::error_code ec;
  if (fs::exists(o.output) && fs::equivalent(o.scene, o.output, ec))
    throw Error(o.output + ": edit never overwrites its input; choose another output");
  if (fs::exists(o.output) && !o.force) throw Error(o.output + ": exists; pass --force to overwrite it");
  Scene scene = readScene(o.scene);
  const size_t before = scene.activeVoxelCount();
  std::printf("read %s: %zu active voxels\n", o.scene.c_str(), before);
  if (!o.exclude.empty()) {
    const std::set<int> ids = resolveClassSelection(scene.meta.classes, o.exclude, "--exclude-classes");
    const size_t n = excludeClassVoxels(scene, ids);
    std::printf("exclude-classes %s: removed %zu voxels\n", classNames(scene.meta.classes, ids).c_str(), n);
  }
  if (!o.crop_box.empty()) {
    if (o.crop_box.size() != 6) throw Error("--crop-box needs six numbers: xmin,ymin,zmin,xmax,ymax,zmax (metres)");
    const size_t n = cropToBox(scene, {o.crop_box[0], o.crop_box[1], o.crop_box[2]},
                               {o.crop_box[3], o.crop_box[4], o.crop_box[5]});
    std::printf("crop-box: removed %zu voxels outside the box\n", n);
  }
  if (o.remove_outliers) {
    OutlierOptions options;
    options.min_weight = o.outlier_min_weight;
    options.min_component_voxels = o.min_component_voxels;
    const OutlierReport r = removeOutliers(scene, options);
    std::printf("remove-outliers: removed %zu voxels observed fewer than %.1f times, %zu pieces (%zu voxels) under "
                "%zu voxels; %zu pieces kept\n",
                r.weak_voxels, o.outlier_min_weight, r.components_removed, r.component_voxels,
                o.min_component_voxels, r.components_kept);
  }
  if (o.smooth > 0) {
    const size_t n = smoothScene(scene, o.smooth);
    std::printf("smooth %d: changed %zu voxel values\n", o.smooth, n);
  }
  if (scene.activeVoxelCount() == 0) throw Error("the edits removed every voxel; nothing written");
  writeScene(scene, o.output);
  std::printf("wrote %s: %zu active voxels (%zu removed)\n", o.output.c_str(), scene.activeVoxelCount(),
              before - scene.activeVoxelCount());
}

void setup(CLI::App& root) {
  auto o = std::make_shared<EditOptions>();
  CLI::App* cmd = root.add_subcommand("edit", "Remove classes, crop, drop outliers or smooth a scene into a new .vdb");
  cmd->add_option("scene", o->scene, "input scene (.vdb), never modified")->required()->check(CLI::ExistingFile);
  cmd->add_option("-o,--output", o->output, "output scene (.vdb)")->required();
  cmd->add_flag("--force", o->force, "overwrite an existing output");
  cmd->add_option("--exclude-classes", o->exclude, "remove the voxels of these classes (names or ids)")->delimiter(',');
  cmd->add_option("--crop-box", o->crop_box, "keep voxels inside xmin,ymin,zmin,xmax,ymax,zmax (metres)")
      ->delimiter(',');
  cmd->add_flag("--remove-outliers", o->remove_outliers, "drop small disconnected pieces and weakly observed voxels");
  cmd->add_option("--min-component-voxels", o->min_component_voxels, "with --remove-outliers: smallest piece kept")
      ->capture_default_str();
  cmd->add_option("--outlier-min-weight", o->outlier_min_weight, "with --remove-outliers: least observations kept")
      ->capture_default_str();
  cmd->add_option("--smooth", o->smooth, "iterations of level-set mean-curvature smoothing")->check(CLI::Range(0, 100));
  cmd->callback([o] { runEdit(*o); });
}

}  // namespace

VF_REGISTER_COMMAND(35, setup);

}  // namespace vf::app
