#include "corridor_geometry.h"

#include <algorithm>
#include <string>

#include "scene_builder.h"

namespace vf::synth {
namespace {

using L = CorridorLayout;
constexpr float kWall_m = 0.25f;
constexpr float kDoorWidth_m = 0.9f, kDoorHeight_m = 2.05f, kDoorSetBack_m = 0.12f;
constexpr float kTrimWidth_m = 0.07f, kTrimProud_m = 0.02f;

// One face of a wall as the corridor sees it: along x (its face at y = face) or along y (at
// x = face); `into` (+1 or -1) points from the wall into the corridor.
struct WallFace {
  std::string name;
  bool along_x;
  float face;
  float into;
};

struct CorridorBuilder {
  SceneBuilder& b;

  // A box against a wall face: [s0, s1] along it, [z0, z1] high, `depth_m` into the corridor
  // (negative: into the wall).
  void mounted(const std::string& name, const WallFace& w, float s0, float s1, float z0, float z1, float depth_m,
               Material m) {
    const float a = w.face, c = w.face + w.into * depth_m;
    const float b0 = std::min(a, c), b1 = std::max(a, c);
    if (w.along_x) b.box(name, s0, s1, b0, b1, z0, z1, m);
    else b.box(name, b0, b1, s0, s1, z0, z1, m);
  }
  // A door set back in its recess (the recess is an opening of the wall slab), with a handle
  // and a white frame 2 cm proud of the wall.
  void door(const std::string& name, const WallFace& w, float s0) {
    const float s1 = s0 + kDoorWidth_m;
    mounted(name, w, s0, s1, 0, kDoorHeight_m, -kWall_m, Material::kWood);
    // The door's face is kDoorSetBack_m behind the wall's: shift the box (it fills the rest).
    b.room.primitives.back().lo[w.along_x ? 1 : 0] += w.into < 0 ? kDoorSetBack_m : 0.f;
    b.room.primitives.back().hi[w.along_x ? 1 : 0] -= w.into > 0 ? kDoorSetBack_m : 0.f;
    const float handle_s = w.into * (w.along_x ? 1.f : -1.f) > 0 ? s1 - 0.15f : s0 + 0.05f;
    WallFace recess = w;
    recess.face = w.face - w.into * kDoorSetBack_m;
    mounted(name + "_handle", recess, handle_s, handle_s + 0.1f, 0.98f, 1.03f, 0.05f, Material::kMetal);
    mounted(name + "_frame_a", w, s0 - kTrimWidth_m, s0, 0, kDoorHeight_m + kTrimWidth_m, kTrimProud_m, Material::kTrim);
    mounted(name + "_frame_b", w, s1, s1 + kTrimWidth_m, 0, kDoorHeight_m + kTrimWidth_m, kTrimProud_m, Material::kTrim);
    mounted(name + "_frame_top", w, s0, s1, kDoorHeight_m, kDoorHeight_m + kTrimWidth_m, kTrimProud_m, Material::kTrim);
  }
  // A fluorescent light 1.2 m long along the corridor, 6 cm below the ceiling.
  void light(const std::string& name, float x, float y, bool along_x) {
    const float hx = along_x ? 0.6f : 0.15f, hy = along_x ? 0.15f : 0.6f;
    b.box(name, x - hx, x + hx, y - hy, y + hy, L::kHeight_m - 0.06f, L::kHeight_m, Material::kTrim);
  }
};

SceneBuilder::Opening doorOpening(float s0) { return {s0, s0 + kDoorWidth_m, 0.f, kDoorHeight_m}; }

}  // namespace

Room makeCorridor() {
  Room room;
  room.interior_lo = Vec3(0, 0, 0);
  room.interior_hi = Vec3(L::kOuterX_m, L::kOuterY_m, L::kHeight_m);
  SceneBuilder b{room, L::kHeight_m};
  CorridorBuilder c{b};
  const float w = kWall_m, X = L::kOuterX_m, Y = L::kOuterY_m;
  const float bx0 = L::kBlockX0_m, bx1 = L::kBlockX1_m, by0 = L::kBlockY0_m, by1 = L::kBlockY1_m;

  // Shell: floor, ceiling and the backs of the openings in the outer walls.
  b.shell(Vec3(-w, -w, 0), Vec3(X + w, Y + w, L::kHeight_m), Material::kCorridorShell);

  // Door positions (start along the wall, increasing x or y), one list per wall: the slabs
  // leave their openings, the doors fill them.
  const float s_out_door = 5.2f, s_in_door_1 = 2.9f, s_in_door_2 = 8.4f;  // south leg
  const float e_out_door = 3.0f;                                         // east leg
  const float n_in_door = 9.7f, n_out_door = 2.8f;                        // north leg
  const WallFace south_out{"south_outer", true, 0.f, 1.f}, north_out{"north_outer", true, Y, -1.f};
  const WallFace west_out{"west_outer", false, 0.f, 1.f}, east_out{"east_outer", false, X, -1.f};
  const WallFace south_in{"south_inner", true, by0, -1.f}, north_in{"north_inner", true, by1, 1.f};
  const WallFace west_in{"west_inner", false, bx0, -1.f}, east_in{"east_inner", false, bx1, 1.f};

  // Outer walls; the west one has a window niche (frosted glass: the painted shell behind).
  b.wall("wall_south_outer", true, -w, X + w, -w, 0, {doorOpening(s_out_door)}, Material::kCorridorWall);
  b.wall("wall_north_outer", true, -w, X + w, Y, Y + w, {doorOpening(n_out_door)}, Material::kCorridorWall);
  b.wall("wall_west_outer", false, 0, Y, -w, 0, {{3.3f, 4.5f, 0.9f, 2.0f}}, Material::kCorridorWall);
  b.wall("wall_east_outer", false, 0, Y, X, X + w, {doorOpening(e_out_door)}, Material::kCorridorWall);

  // The block: a core, and slabs round it with the recesses of its doors.
  b.box("block_core", bx0 + w, bx1 - w, by0 + w, by1 - w, 0, L::kHeight_m, Material::kCorridorWall);
  b.wall("wall_south_inner", true, bx0, bx1, by0, by0 + w, {doorOpening(s_in_door_1), doorOpening(s_in_door_2)},
         Material::kCorridorWall);
  b.wall("wall_north_inner", true, bx0, bx1, by1 - w, by1, {doorOpening(n_in_door)}, Material::kCorridorWall);
  b.wall("wall_west_inner", false, by0 + w, by1 - w, bx0, bx0 + w, {}, Material::kCorridorWall);
  b.wall("wall_east_inner", false, by0 + w, by1 - w, bx1 - w, bx1, {}, Material::kCorridorWall);

  // South leg (the walk starts here at x = 4, going east): doors on both sides, a pilaster, a
  // bench and a notice board behind the start, an extinguisher, two lights.
  c.door("door_south_outer", south_out, s_out_door);
  c.door("door_south_inner_1", south_in, s_in_door_1);
  c.door("door_south_inner_2", south_in, s_in_door_2);
  c.mounted("pilaster_south", south_in, 6.8f, 7.1f, 0, L::kHeight_m, 0.15f, Material::kCorridorWall);
  c.mounted("bench_south", south_in, 3.95f, 5.0f, 0, 0.45f, 0.4f, Material::kLightWood);
  c.mounted("notice_board_south", south_out, 2.4f, 3.4f, 1.1f, 1.8f, 0.015f, Material::kPicture);
  b.cylinder("extinguisher_south", 7.6f, 0.1f, 0.08f, 0.6f, 1.1f, Material::kExtinguisher);
  c.light("light_south_1", 5.6f, 1.f, true);
  c.light("light_south_2", 8.0f, 1.f, true);
  // South-east corner: a plant.
  b.cylinder("plant_pot_southeast", 12.55f, 0.45f, 0.22f, 0, 0.5f, Material::kPot);
  b.sphere("plant_southeast", 12.55f, 0.45f, 0.85f, 0.35f, Material::kFoliage);

  // East leg (north-bound): a door, a radiator, a poster, a light; a bin in the north-east corner.
  c.door("door_east_outer", east_out, e_out_door);
  c.mounted("radiator_east", east_in, 4.2f, 5.2f, 0.15f, 0.75f, 0.1f, Material::kRadiator);
  c.mounted("poster_east", east_out, 4.6f, 5.3f, 1.2f, 1.8f, 0.01f, Material::kPicture);
  c.light("light_east", 12.f, 4.f, false);
  b.cylinder("bin_northeast", 12.7f, 7.7f, 0.2f, 0, 0.6f, Material::kMetal);
  // The wall the camera faces as it turns the corner: a fire hose cabinet and an extinguisher,
  // so that the turn does not see one plain wall alone (the cabinet's front is parallel to the
  // wall; its side and the extinguisher's curve are what pin the camera along it).
  c.mounted("hose_cabinet_northeast", north_out, 12.2f, 12.8f, 1.0f, 1.6f, 0.2f, Material::kExtinguisher);
  b.cylinder("extinguisher_northeast", 11.35f, 7.9f, 0.09f, 0.9f, 1.4f, Material::kExtinguisher);

  // North leg (west-bound): a door and a pilaster at its east end, then the plain stretch from
  // x = 8.9 to 3.8 (L::kPlainX0_m..kPlainX1_m), then a door and a light at its west end.
  c.door("door_north_inner", north_in, n_in_door);
  c.mounted("pilaster_north", north_out, L::kPlainX1_m, L::kPlainX1_m + 0.3f, 0, L::kHeight_m, 0.15f,
            Material::kCorridorWall);
  c.light("light_north_1", 10.f, 7.f, true);
  c.door("door_north_outer", north_out, n_out_door);
  c.light("light_north_2", 2.6f, 7.f, true);
  // North-west corner: a coat stand, and a hose cabinet on the wall the turn faces.
  b.cylinder("coat_stand_pole", 0.4f, 7.6f, 0.025f, 0, 1.75f, Material::kMetal);
  b.sphere("coat_stand_coats", 0.4f, 7.6f, 1.45f, 0.2f, Material::kFabric);
  c.mounted("hose_cabinet_northwest", west_out, 5.9f, 6.5f, 1.0f, 1.6f, 0.2f, Material::kExtinguisher);

  // West leg (south-bound): the window niche, a cabinet, a radiator, a light; boxes in the
  // south-west corner.
  c.mounted("cabinet_west", west_in, 4.6f, 5.4f, 0, 1.0f, 0.5f, Material::kLightWood);
  c.mounted("radiator_west", west_out, 2.2f, 3.0f, 0.15f, 0.75f, 0.1f, Material::kRadiator);
  c.light("light_west", 1.f, 3.f, false);
  b.box("boxes_southwest_low", 0.15f, 0.65f, 0.15f, 0.6f, 0, 0.45f, Material::kCardboard);
  b.box("boxes_southwest_high", 0.2f, 0.55f, 0.2f, 0.5f, 0.45f, 0.75f, Material::kCardboard);
  return room;
}

}  // namespace vf::synth
