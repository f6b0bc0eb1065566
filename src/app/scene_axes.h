#pragma once
// --axes of mesh and export: which frame a file is written in (vdb/scene_frame.h), by default
// the one its usual importer expects.
#include <string>

#include "core/math.h"
#include "io/mesh_io.h"
#include "vdb/scene.h"
#include "vdb/scene_frame.h"

namespace vf::app {

inline constexpr const char* kAxesHelp =
    "frame of the written file: camera (as fused), z-up (Blender, PLY) or y-up (glTF, OBJ; -Z forward); "
    "default: z-up for .ply, y-up for .obj/.glb";

// `option` empty: the format's default (PLY z-up; OBJ and GLB y-up, as Blender's importers expect).
SceneAxes axesFor(const std::string& option, MeshFormat format);

// The rotation into `axes`. A scene written before its up was recorded gets it estimated now
// (from the trajectory beside it, scene.vdb -> scene.txt, when there is one), and says so.
Rigid3f exportRotationFor(Scene& scene, const std::string& scene_path, SceneAxes axes);

}  // namespace vf::app
