// vdbfuse info: what a scene document holds. By default from the file's headers alone (metadata
// and the per-grid statistics libopenvdb writes): milliseconds for any scene. --extent reads the
// grids for what only the voxels tell: the surface's voxels and extent, the voxels per class.
#include <cstdio>
#include <memory>
#include <string>

#include "app/command_registry.h"
#include "vdb/scene.h"
#include "vdb/scene_frame.h"
#include "vdb/scene_info.h"

namespace vf::app {
namespace {

struct InfoOptions {
  std::string path;
  bool extent = false;
};

// `s` from readSceneHeader (extent false: no surface or class counts) or summarizeScene.
void printInfo(const std::string& path, const SceneMetadata& m, const SceneSummary& s, bool extent,
               bool has_classes) {
  const bool up_known = norm(m.up_world) > 0;
  std::printf("scene        %s\n", path.c_str());
  std::printf("source       %s (%d frames, vdbfuse %s)\n", m.source.empty() ? "?" : m.source.c_str(), m.frame_count,
              m.software_version.c_str());
  std::printf("voxel        %.2f mm, truncation %.2f mm\n", m.voxel_size_m * 1e3, m.truncation_m * 1e3);
  if (extent)
    std::printf("active       %zu voxels (%zu on the surface)\n", s.active_voxels, s.surface_voxels);
  else
    std::printf("active       %zu voxels\n", s.active_voxels);
  if (!s.empty)
    std::printf("bounds       [%.3f %.3f %.3f] .. [%.3f %.3f %.3f] m (%.2f x %.2f x %.2f m)\n", s.bounds_min_m.x,
                s.bounds_min_m.y, s.bounds_min_m.z, s.bounds_max_m.x, s.bounds_max_m.y, s.bounds_max_m.z,
                s.bounds_max_m.x - s.bounds_min_m.x, s.bounds_max_m.y - s.bounds_min_m.y,
                s.bounds_max_m.z - s.bounds_min_m.z);
  if (up_known) {
    std::printf("up           [%.3f %.3f %.3f] from %s; forward [%.3f %.3f %.3f]\n", m.up_world.x, m.up_world.y,
                m.up_world.z, m.up_source.c_str(), m.forward_world.x, m.forward_world.y, m.forward_world.z);
    // Where the surface lies in the frame of a PLY export (what Blender shows; edit --crop-axes z-up).
    if (!extent)
      std::printf("surface z-up (info --extent reads the voxels to measure it)\n");
    else if (s.surface_voxels > 0)
      std::printf("surface z-up [%.3f %.3f %.3f] .. [%.3f %.3f %.3f] m, as PLY exports and edit --crop-axes z-up\n",
                  s.surface_min_m.x, s.surface_min_m.y, s.surface_min_m.z, s.surface_max_m.x, s.surface_max_m.y,
                  s.surface_max_m.z);
  } else {
    std::printf("up           not recorded (exports estimate it)\n");
  }
  if (m.depth_intrinsics.valid())
    std::printf("camera       %dx%d, fx %.1f fy %.1f cx %.1f cy %.1f\n", m.depth_intrinsics.width,
                m.depth_intrinsics.height, m.depth_intrinsics.fx, m.depth_intrinsics.fy, m.depth_intrinsics.cx,
                m.depth_intrinsics.cy);
  std::printf("memory       %.1f MiB\n\ngrids\n", s.memory_bytes / 1048576.0);
  for (const GridSummary& g : s.grids)
    std::printf("  %-17s %-7s %12zu active %9.1f MiB\n", g.name.c_str(), g.value_type.c_str(), g.active_voxels,
                g.memory_bytes / 1048576.0);
  if (m.classes.empty() && !has_classes) return;
  if (extent) {
    std::printf("\nclasses (%zu in table)\n", m.classes.classes.size());
    for (const ClassVoxelCount& c : s.classes)
      std::printf("  %5d %-24s %12zu voxels\n", c.id, c.name.c_str(), c.voxels);
  } else {
    std::printf("\nclasses (%zu in table; info --extent counts the voxels of each)\n", m.classes.classes.size());
    for (const ClassInfo& c : m.classes.classes) std::printf("  %5d %s\n", c.id, c.name.c_str());
  }
}

void runInfo(const InfoOptions& o) {
  if (!o.extent) {
    const SceneHeader h = readSceneHeader(o.path);
    if (h.statistics_recorded) {
      printInfo(o.path, h.meta, h.summary, false, h.has_classes);
      return;
    }
    std::printf("note: the file's grids do not record their voxel counts; reading the voxels\n");
  }
  const Scene scene = readScene(o.path);
  const SceneMetadata& m = scene.meta;
  const bool up_known = norm(m.up_world) > 0;
  const SceneSummary s = summarizeScene(scene, exportRotation(m, up_known ? SceneAxes::kZUp : SceneAxes::kCamera));
  printInfo(o.path, m, s, true, scene.hasClasses());
}

void setupInfoCommand(CLI::App& root) {
  auto o = std::make_shared<InfoOptions>();
  CLI::App* cmd = root.add_subcommand("info", "Show a scene's grids, active voxels, bounds, memory and classes "
                                              "(from the file's headers: milliseconds at any size)");
  cmd->add_option("scene", o->path, "scene document (.vdb)")->required();
  cmd->add_flag("--extent", o->extent,
                "also read the voxels: the surface's voxel count and extent (z-up) and the voxels of each class "
                "(seconds and about 5x the file's size in memory for a large scene)");
  cmd->callback([o] { runInfo(*o); });
}

}  // namespace

VF_REGISTER_COMMAND(30, setupInfoCommand);

}  // namespace vf::app
