#pragma once
// Everything the viewer shows, read from a scene document into plain data: the surface split
// by class (so that hiding a class is only an actor's visibility), the class panel's rows, the
// trajectory. OpenVDB stays in src/vdb; the Scene is kept for slicing.
#include <cstddef>
#include <string>
#include <vector>

#include "core/mesh.h"
#include "core/pose.h"
#include "vdb/scene.h"
#include "vdb/scene_info.h"
#include "viewer/level_frame.h"

namespace vf::viewer {

// One row of the class panel.
struct ClassRow {
  int id = kSceneUnknownClass;
  std::string name;
  Rgb8 color{128, 128, 128, 255};
  size_t voxels = 0;     // active class-grid voxels (summarizeScene)
  size_t triangles = 0;  // faces of this class in the surface
};

// The faces of one class, with both colorings per vertex: mesh.colors holds the fused RGB,
// class_colors the class table's color (so toggling the coloring needs no second meshing).
struct ClassPart {
  int id = kSceneUnknownClass;
  TriangleMesh mesh;
  std::vector<Rgb8> class_colors;
};

struct SceneContent {
  std::string scene_path;
  Scene scene;
  SceneSummary summary;
  std::vector<ClassRow> rows;    // empty when the scene has no class grid; unknown class last
  std::vector<ClassPart> parts;  // one per row (same order), or a single part without classes
  size_t triangles = 0;
  Vec3f surface_min_m{0, 0, 0}, surface_max_m{0, 0, 0};  // bounds of the surface's vertices
  // Up, heading and floor: the presets' and floor plans' frame. Up and forward as the scene
  // records them; estimated (as exports do, vdb/scene_frame.h) for a scene that does not.
  LevelFrame frame;

  Trajectory trajectory;        // empty when none was found or asked for
  std::string trajectory_path;  // where it was read from
  std::vector<std::string> notices;  // for the user: missing trajectory, ...

  double read_s = 0, mesh_s = 0, split_s = 0;  // mesh_s includes the summary, computed beside it
};

// The class table's color for `id`, gray for ids it lacks (as meshScene colors them), lightened
// to kMinClassLuma when darker so that it shows on the backdrop.
Rgb8 classColor(const ClassTable& table, int id);
Rgb8 visibleOnBackdrop(Rgb8 color);

// Reads the scene, meshes it (RGB colors, per-vertex classes) and splits it by class.
// `trajectory_path` empty: the file beside the scene if there is one; `load_trajectory` false:
// none. Throws vf::Error for an unreadable scene, an empty one (no observed voxel) and a named
// trajectory that cannot be read.
SceneContent loadSceneContent(const std::string& scene_path, const std::string& trajectory_path,
                              bool load_trajectory, float min_weight);

// Index of the panel row of class `key` (a name or a numeric id); -1 when there is none.
int findClassRow(const std::vector<ClassRow>& rows, const std::string& key);

// Concatenation of meshes (vertices renumbered); attributes are kept only when every input has them.
TriangleMesh mergeMeshes(const std::vector<const TriangleMesh*>& meshes);

}  // namespace vf::viewer
