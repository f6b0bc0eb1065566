#pragma once
// The synthetic room's known surface: a few dozen solids (axis-aligned boxes, spheres, upright
// cylinders) inside an inward-facing shell. Everything that renders or evaluates the room asks
// this description, so the depth maps and the ground truth cannot disagree.
//
// World frame: metres, z up, the floor at z = 0, the room's interior x in [0, 8], y in [0, 6],
// z in [0, 2.6]. The shell is 0.25 m larger on the four walls; wall slabs fill that band except
// where a niche or the door recess opens into it.
#include <Eigen/Core>
#include <string>
#include <vector>

namespace vf::synth {

using Vec3 = Eigen::Vector3f;

// What a surface looks like (room_texture.h paints each one).
// kShell paints the shell by its normal: floor boards, ceiling, brick in the niches. The
// corridor's materials (after kMetal) are weakly textured, as real corridors: low-contrast paint,
// linoleum, white trim (kCorridorShell: linoleum floor, plain ceiling, painted recess backs).
enum class Material {
  kShell, kWall, kDoor, kWood, kLightWood, kFabric, kBook, kPicture, kPainted, kCardboard, kBall, kPot, kFoliage, kMetal,
  kCorridorShell, kCorridorWall, kTrim, kRadiator, kExtinguisher,
};

struct Primitive {
  enum class Kind { kBox, kShell, kSphere, kCylinder };
  Kind kind = Kind::kBox;
  // Box and shell: the box itself (the shell is its inside). Sphere and cylinder: their bounds.
  Vec3 lo = Vec3::Zero(), hi = Vec3::Zero();
  Vec3 center = Vec3::Zero();  // sphere centre; cylinder: axis at (center.x, center.y)
  float radius = 0;            // sphere, cylinder (z from lo.z to hi.z)
  Material material = Material::kWall;
  int variant = 0;             // varies the colour between primitives of one material
  std::string name;
};

struct Hit {
  float t = 0;          // distance along the unit ray
  Vec3 normal = Vec3::Zero();  // unit, facing the ray's origin side (out of the solid)
  int primitive = -1;
};

// Ray (origin, unit direction, its component-wise inverse) against one primitive: the first
// intersection with t in (1e-5, t_max). The ray is assumed to start outside every solid.
bool intersect(const Primitive& p, const Vec3& origin, const Vec3& dir, const Vec3& inv_dir, float t_max, Hit& hit);

// Signed distance to the primitive's solid (negative inside). The shell's solid is everything
// outside its box, so points in the room are at positive distance from it.
float signedDistance(const Primitive& p, const Vec3& point);

// Unit outward normal of the solid at a point on (or near) its surface.
Vec3 surfaceNormal(const Primitive& p, const Vec3& point);

struct Room {
  std::vector<Primitive> primitives;
  Vec3 interior_lo = Vec3::Zero(), interior_hi = Vec3::Zero();  // the walls' inner faces

  // Nearest hit over all primitives (or over `candidates` when given), t in (1e-5, t_max).
  bool intersect(const Vec3& origin, const Vec3& dir, float t_max, Hit& hit,
                 const std::vector<int>* candidates = nullptr) const;
  // Distance from a point to the nearest surface of the room: exact for points in free space;
  // for a point inside a solid, the distance to that solid's own surface.
  float distanceToSurface(const Vec3& point) const;
  // Same, leaving one primitive out (what a mesh without that primitive has left).
  float distanceToSurfaceWithout(const Vec3& point, int left_out) const;
  // True when the point lies inside some solid other than `except` by more than `margin_m`.
  bool insideSolid(const Vec3& point, int except, float margin_m) const;
  int find(const std::string& name) const;  // index of the named primitive, -1 if none
};

// The room this sample scans: 8 x 6 x 2.6 m, with a table and its objects, a bookcase, a sofa,
// a sideboard, an armchair, boxes, a plant, a bin, pictures, two wall niches and a door recess.
Room makeRoom();

}  // namespace vf::synth
