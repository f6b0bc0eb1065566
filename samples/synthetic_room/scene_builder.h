#pragma once
// Adds named solids to a scene (Room) one by one, numbering their texture variants in order. The
// room and the corridor are both built with it, so that a wall with a door or niche in it is cut
// into slabs the same way in both.
#include <string>
#include <vector>

#include "room_geometry.h"

namespace vf::synth {

struct SceneBuilder {
  Room& room;
  float height_m;        // floor to ceiling: walls and openings run up to it
  int next_variant = 0;  // the variant of the next primitive (varies its colour)

  void box(const std::string& name, float x0, float x1, float y0, float y1, float z0, float z1, Material m);
  void sphere(const std::string& name, float x, float y, float z, float r, Material m);
  void cylinder(const std::string& name, float x, float y, float r, float z0, float z1, Material m);
  // The inward-facing box that closes the scene: floor, ceiling and the backs of wall openings.
  void shell(const Vec3& lo, const Vec3& hi, Material m);

  // An opening in a wall: [s0, s1] along the wall, [z0, z1] in height.
  struct Opening {
    float s0, s1, z0, z1;
  };
  // A floor-to-ceiling wall slab along x (along_x) or y, between `a0` and `a1` along it and
  // `b0`..`b1` across, cut into boxes of `material` around its openings (sorted along the wall,
  // not overlapping). Pieces are named name_0, name_1, ...
  void wall(const std::string& name, bool along_x, float a0, float a1, float b0, float b1,
            const std::vector<Opening>& openings, Material material = Material::kWall);
};

}  // namespace vf::synth
