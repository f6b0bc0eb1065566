#include "app/scene_axes.h"

#include <cstdio>
#include <filesystem>

#include "io/trajectory_io.h"

namespace vf::app {

SceneAxes axesFor(const std::string& option, MeshFormat format) {
  if (!option.empty()) return parseSceneAxes(option);
  return format == MeshFormat::kPly ? SceneAxes::kZUp : SceneAxes::kYUp;
}

Rigid3f exportRotationFor(Scene& scene, const std::string& scene_path, SceneAxes axes) {
  if (axes != SceneAxes::kCamera && norm(scene.meta.up_world) == 0) {
    const std::string beside = std::filesystem::path(scene_path).replace_extension(".txt").string();
    Trajectory trajectory;
    if (std::filesystem::exists(beside)) trajectory = readTumTrajectory(beside);
    const SceneUp up = setSceneFrame(scene, trajectory);
    std::printf("up: the scene does not record it; estimated from the %s (%s%s%s)\n", up.source.c_str(),
                up.detail.c_str(), trajectory.empty() ? "" : ", trajectory ", trajectory.empty() ? "" : beside.c_str());
  }
  return exportRotation(scene.meta, axes);
}

}  // namespace vf::app
