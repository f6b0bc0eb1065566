#pragma once
// The scene's level frame, in which the viewer lays out its camera presets and floor-plan
// slices: up against gravity and forward, the first camera's heading made horizontal, as the
// scene records them (SceneMetadata::up_world / forward_world, vdb/scene_frame.h; every export
// uses the same pair), right = forward x up; and the floor's height along up.
// Plain C++: tested without a display.
#include <string>
#include <vector>

#include "core/math.h"
#include "core/mesh.h"
#include "viewer/view_options.h"

namespace vf::viewer {

struct LevelFrame {
  Vec3f up{0, -1, 0}, forward{0, 0, 1}, right{1, 0, 0};  // unit, orthogonal, world (scene) coordinates
  std::string up_source;  // as SceneMetadata::up_source, or how the viewer estimated it
  double floor_m = 0;     // the floor's height: dot(p, up) for a point p on it
  // The surface's extent in frame coordinates: x along right, y along forward, z along up.
  Vec3f min{0, 0, 0}, max{0, 0, 0};

  // World point -> frame coordinates (right, forward, up components) and back.
  Vec3f toFrame(Vec3f p) const { return {dot(p, right), dot(p, forward), dot(p, up)}; }
  Vec3f toWorld(Vec3f q) const { return right * q.x + forward * q.y + up * q.z; }
};

// The frame for `up` and `forward` (unit and orthogonal, as SceneMetadata holds them), with the
// floor and extent taken from the vertices of `surface`.
LevelFrame levelFrame(Vec3f up, Vec3f forward, const std::vector<const TriangleMesh*>& surface);

// The floor's height among the heights (dot(p, up)) of surface vertices: a floor is the large
// horizontal surface at the bottom, so the densest 2 cm layer within 10 cm below to 30 cm above
// the 1st percentile (which a few stray vertices under the floor cannot move far), refined to
// the median height of the vertices in that layer and its two neighbours. Empty: 0.
double floorHeight(std::vector<float> heights);

// A camera preset as directions: `direction` the view direction, `view_up` the picture's up.
// front: the first camera's heading, level (view_up = up); side: turned 90 degrees about up,
// looking along right; top: looking down along -up with forward at the top of the picture.
struct PresetView {
  Vec3f direction, view_up;
};
PresetView presetView(const LevelFrame& frame, CameraPreset preset);

}  // namespace vf::viewer
