#pragma once
// The scene document: the sparse OpenVDB grids fusion produces and the editor works on
// (DESIGN.md, "The scene document"). OpenVDB stays behind SceneGrids (vdb/scene_grids.h) so that
// the app and other modules include this header without compiling OpenVDB templates.
#include <cstddef>
#include <memory>
#include <string>

#include "core/brick_volume.h"
#include "core/class_table.h"
#include "core/intrinsics.h"

namespace vf {

struct SceneGrids;  // OpenVDB grids; defined in vdb/scene_grids.h, only src/vdb includes it

// What the .vdb file records besides the grids.
struct SceneMetadata {
  float voxel_size_m = 0;
  float truncation_m = 0;
  ClassTable classes;             // id -> name/color; empty when fused without labels
  std::string source;             // e.g. the input folder or capture file
  int frame_count = 0;            // frames fused
  std::string software_version;   // empty = this build's VDBFUSE_VERSION_STRING when written
  // Where "up" (against gravity) and the horizontal heading lie, as unit vectors in the scene's
  // own (fusion world) coordinates, and how up was found (vdb/scene_frame.h: "recorded poses",
  // "floor plane", "camera up-vectors"); zero / empty when not known. The grids stay in the
  // fusion world; exporters rotate by these, so every export maps back to the scene.
  Vec3f up_world{0, 0, 0};
  Vec3f forward_world{0, 0, 0};
  std::string up_source;
  Intrinsics depth_intrinsics;    // of the fused frames (frame cameras' field of view); fx = 0: unknown
  // What a texture bake needs to find the frames again (app/bake_frames.h): the fused frames'
  // poses as TUM text, and how the source was opened (JSON: format, depth scale, intrinsics,
  // label folder, dynamic classes). Empty in scenes written before they were recorded.
  std::string trajectory_tum;
  std::string source_options_json;
};

// Grid names in the file (DESIGN.md table).
inline constexpr const char* kTsdfGridName = "tsdf";
inline constexpr const char* kWeightGridName = "weight";
inline constexpr const char* kColorGridName = "color";
inline constexpr const char* kClassGridName = "class";
inline constexpr const char* kClassConfidenceGridName = "class_confidence";
// Value of the class grid where no class was fused.
inline constexpr int kSceneUnknownClass = -1;

// Grids + metadata. Move-only: an edit works on an explicit clone() so the input stays intact.
class Scene {
 public:
  Scene();
  ~Scene();
  Scene(Scene&&) noexcept;
  Scene& operator=(Scene&&) noexcept;
  Scene(const Scene&) = delete;
  Scene& operator=(const Scene&) = delete;

  Scene clone() const;  // deep copy of every grid
  bool hasClasses() const;
  size_t activeVoxelCount() const;  // active voxels of the tsdf grid

  SceneGrids& grids() { return *grids_; }
  const SceneGrids& grids() const { return *grids_; }

  SceneMetadata meta;

 private:
  std::unique_ptr<SceneGrids> grids_;
};

// The fused bricks as grids: each brick becomes one leaf at the same coordinates, and its voxels
// with weight > 0 become active. Parallel over bricks. meta.voxel_size_m / truncation_m are taken
// from the bricks (the arguments' values are ignored).
Scene sceneFromBricks(const BrickVolumeView& bricks, const SceneMetadata& meta);

// Writes grids + metadata to a temp file beside `path` and renames it into place; on error no
// file is left behind. Throws vf::Error naming the path.
void writeScene(const Scene& scene, const std::string& path);

// writeScene(sceneFromBricks(bricks, meta), path), the same file byte for byte but for its
// random UUID, without holding the grids: each grid's topology is built without voxel values
// and its leaves are converted and compressed from the bricks in parallel, a batch at a time,
// as they are written. Memory stays a small fraction of the bricks' (the grids in memory take
// twice the bricks, and a 10 m room's did not fit beside them in 1.5 GB). Returns the number of
// active voxels written.
size_t writeSceneFromBricks(const BrickVolumeView& bricks, const SceneMetadata& meta, const std::string& path);

// Reads a scene written by writeScene (or any .vdb with its grids). Throws vf::Error naming the
// path for a missing, truncated, damaged or foreign file, or one without a `tsdf` level set; the
// file's structure is checked (vdb/vdb_file_check.h) before libopenvdb allocates anything it states.
Scene readScene(const std::string& path);

}  // namespace vf
