#include "room_geometry.h"

#include <algorithm>
#include <cmath>
#include <limits>

#include "scene_builder.h"

namespace vf::synth {
namespace {

constexpr float kEps = 1e-5f;

int maxAxis(const Vec3& v) {
  return v.x() >= v.y() ? (v.x() >= v.z() ? 0 : 2) : (v.y() >= v.z() ? 1 : 2);
}
int minAxis(const Vec3& v) {
  return v.x() <= v.y() ? (v.x() <= v.z() ? 0 : 2) : (v.y() <= v.z() ? 1 : 2);
}

float boxSignedDistance(const Vec3& lo, const Vec3& hi, const Vec3& p) {
  const Vec3 q = (lo - p).cwiseMax(p - hi);  // per axis: > 0 outside that slab
  return q.cwiseMax(0.f).norm() + std::min(q.maxCoeff(), 0.f);
}

}  // namespace

bool intersect(const Primitive& p, const Vec3& o, const Vec3& d, const Vec3& inv, float t_max, Hit& hit) {
  switch (p.kind) {
    case Primitive::Kind::kBox:
    case Primitive::Kind::kShell: {
      const Vec3 t1 = (p.lo - o).cwiseProduct(inv), t2 = (p.hi - o).cwiseProduct(inv);
      const Vec3 near = t1.cwiseMin(t2), far = t1.cwiseMax(t2);
      const float t_near = near.maxCoeff(), t_far = far.minCoeff();
      if (t_near > t_far) return false;
      const bool shell = p.kind == Primitive::Kind::kShell;
      const float t = shell ? t_far : t_near;
      if (t <= kEps || t >= t_max) return false;
      const int axis = shell ? minAxis(far) : maxAxis(near);
      hit.t = t;
      hit.normal = Vec3::Zero();
      hit.normal[axis] = d[axis] > 0 ? -1.f : 1.f;  // both cases face back along the ray
      return true;
    }
    case Primitive::Kind::kSphere: {
      const Vec3 oc = o - p.center;
      const float b = oc.dot(d), c = oc.squaredNorm() - p.radius * p.radius;
      const float disc = b * b - c;
      if (disc < 0) return false;
      const float t = -b - std::sqrt(disc);
      if (t <= kEps || t >= t_max) return false;
      hit.t = t;
      hit.normal = (oc + t * d) / p.radius;
      return true;
    }
    case Primitive::Kind::kCylinder: {
      bool found = false;
      float best = t_max;
      Vec3 normal = Vec3::Zero();
      const float ox = o.x() - p.center.x(), oy = o.y() - p.center.y();
      const float a = d.x() * d.x() + d.y() * d.y();
      if (a > 1e-12f) {
        const float b = ox * d.x() + oy * d.y(), c = ox * ox + oy * oy - p.radius * p.radius;
        const float disc = b * b - a * c;
        if (disc >= 0) {
          const float t = (-b - std::sqrt(disc)) / a;
          const float z = o.z() + t * d.z();
          if (t > kEps && t < best && z >= p.lo.z() && z <= p.hi.z()) {
            best = t;
            normal = Vec3(ox + t * d.x(), oy + t * d.y(), 0) / p.radius;
            found = true;
          }
        }
      }
      // Caps: only the one facing the origin can be the first hit.
      const bool above = o.z() > p.hi.z();
      if ((above && d.z() < 0) || (o.z() < p.lo.z() && d.z() > 0)) {
        const float zc = above ? p.hi.z() : p.lo.z();
        const float t = (zc - o.z()) * inv.z();
        const float x = ox + t * d.x(), y = oy + t * d.y();
        if (t > kEps && t < best && x * x + y * y <= p.radius * p.radius) {
          best = t;
          normal = Vec3(0, 0, above ? 1.f : -1.f);
          found = true;
        }
      }
      if (!found) return false;
      hit.t = best;
      hit.normal = normal;
      return true;
    }
  }
  return false;
}

float signedDistance(const Primitive& p, const Vec3& x) {
  switch (p.kind) {
    case Primitive::Kind::kBox: return boxSignedDistance(p.lo, p.hi, x);
    case Primitive::Kind::kShell: return -boxSignedDistance(p.lo, p.hi, x);
    case Primitive::Kind::kSphere: return (x - p.center).norm() - p.radius;
    case Primitive::Kind::kCylinder: {
      const float dr = std::hypot(x.x() - p.center.x(), x.y() - p.center.y()) - p.radius;
      const float dz = std::max(p.lo.z() - x.z(), x.z() - p.hi.z());
      return std::hypot(std::max(dr, 0.f), std::max(dz, 0.f)) + std::min(std::max(dr, dz), 0.f);
    }
  }
  return std::numeric_limits<float>::infinity();
}

Vec3 surfaceNormal(const Primitive& p, const Vec3& x) {
  switch (p.kind) {
    case Primitive::Kind::kBox: {
      const Vec3 below = p.lo - x, above = x - p.hi;  // > 0 outside that face
      const Vec3 q = below.cwiseMax(above);
      const int axis = maxAxis(q);
      Vec3 n = Vec3::Zero();
      n[axis] = below[axis] > above[axis] ? -1.f : 1.f;
      return n;
    }
    case Primitive::Kind::kShell: {
      const Vec3 to_lo = x - p.lo, to_hi = p.hi - x;  // distances to the faces from inside
      const Vec3 q = to_lo.cwiseMin(to_hi);
      const int axis = minAxis(q);
      Vec3 n = Vec3::Zero();
      n[axis] = to_lo[axis] < to_hi[axis] ? 1.f : -1.f;  // into the room
      return n;
    }
    case Primitive::Kind::kSphere: return (x - p.center).normalized();
    case Primitive::Kind::kCylinder: {
      const Vec3 radial(x.x() - p.center.x(), x.y() - p.center.y(), 0);
      const float dr = std::abs(radial.norm() - p.radius);
      const float d_top = std::abs(x.z() - p.hi.z()), d_bottom = std::abs(x.z() - p.lo.z());
      if (std::min(d_top, d_bottom) < dr) return Vec3(0, 0, d_top < d_bottom ? 1.f : -1.f);
      return radial.normalized();
    }
  }
  return Vec3::UnitZ();
}

bool Room::intersect(const Vec3& o, const Vec3& d, float t_max, Hit& hit, const std::vector<int>* candidates) const {
  const Vec3 inv = d.cwiseInverse();
  bool found = false;
  Hit h;
  auto test = [&](int i) {
    if (vf::synth::intersect(primitives[size_t(i)], o, d, inv, t_max, h)) {
      t_max = h.t;
      hit = h;
      hit.primitive = i;
      found = true;
    }
  };
  if (candidates) {
    for (int i : *candidates) test(i);
  } else {
    for (int i = 0; i < int(primitives.size()); ++i) test(i);
  }
  return found;
}

float Room::distanceToSurface(const Vec3& x) const { return distanceToSurfaceWithout(x, -1); }

float Room::distanceToSurfaceWithout(const Vec3& x, int left_out) const {
  float outside = std::numeric_limits<float>::infinity();  // min over solids not containing x
  float inside = std::numeric_limits<float>::infinity();   // nearest own surface of a solid containing x
  for (int i = 0; i < int(primitives.size()); ++i) {
    if (i == left_out) continue;
    const float sd = signedDistance(primitives[size_t(i)], x);
    if (sd >= 0) outside = std::min(outside, sd);
    else inside = std::min(inside, -sd);
  }
  return std::isfinite(inside) ? inside : outside + 0.f;  // + 0: no -0 from a point on a face
}

bool Room::insideSolid(const Vec3& x, int except, float margin_m) const {
  for (int i = 0; i < int(primitives.size()); ++i)
    if (i != except && signedDistance(primitives[size_t(i)], x) < -margin_m) return true;
  return false;
}

int Room::find(const std::string& name) const {
  for (int i = 0; i < int(primitives.size()); ++i)
    if (primitives[size_t(i)].name == name) return i;
  return -1;
}

// ---- the layout ------------------------------------------------------------------------------

namespace {

constexpr float kLengthX = 8.0f, kWidthY = 6.0f, kHeightZ = 2.6f;
constexpr float kWallThickness = 0.25f;

}  // namespace

Room makeRoom() {
  Room room;
  room.interior_lo = Vec3(0, 0, 0);
  room.interior_hi = Vec3(kLengthX, kWidthY, kHeightZ);
  SceneBuilder b{room, kHeightZ};
  const float w = kWallThickness;

  // Shell: floor, ceiling, and the backs of the niches and of the door recess.
  b.shell(Vec3(-w, -w, 0), Vec3(kLengthX + w, kWidthY + w, kHeightZ), Material::kShell);

  // Walls. West (x = 0): a picture niche above the sofa. East (x = 8): a window niche.
  // South (y = 0): the door recess. North (y = 6): plain, the bookcase stands there.
  b.wall("wall_west", false, 0, kWidthY, -w, 0, {{2.6f, 3.6f, 1.3f, 1.9f}});
  b.wall("wall_east", false, 0, kWidthY, kLengthX, kLengthX + w, {{3.8f, 5.0f, 0.9f, 2.0f}});
  b.wall("wall_south", true, -w, kLengthX + w, -w, 0, {{6.2f, 7.1f, 0.f, 2.05f}});
  b.wall("wall_north", true, -w, kLengthX + w, kWidthY, kWidthY + w, {});

  // The door, set back 0.12 m in its recess, and its handle.
  b.box("door", 6.2f, 7.1f, -w, -0.12f, 0, 2.05f, Material::kDoor);
  b.box("door_handle", 6.95f, 7.05f, -0.12f, -0.07f, 0.98f, 1.03f, Material::kMetal);

  // Pictures, 3 cm proud of the walls.
  b.box("picture_south", 3.3f, 4.6f, 0, 0.03f, 1.2f, 1.9f, Material::kPicture);
  b.box("picture_north", 5.2f, 6.4f, kWidthY - 0.03f, kWidthY, 1.1f, 1.8f, Material::kPicture);
  b.box("picture_east", kLengthX - 0.03f, kLengthX, 1.6f, 2.6f, 1.2f, 1.8f, Material::kPicture);
  b.box("picture_west", 0, 0.03f, 4.4f, 5.2f, 1.2f, 1.8f, Material::kPicture);

  // Table by the east wall, with a ball, a stack of books and a vase; a stool beside it.
  b.box("table_top", 6.3f, 7.5f, 1.8f, 3.2f, 0.72f, 0.76f, Material::kWood);
  for (int i = 0; i < 4; ++i) {
    const float x = i % 2 ? 7.40f : 6.35f, y = i / 2 ? 3.10f : 1.85f;
    b.box("table_leg_" + std::to_string(i), x, x + 0.05f, y, y + 0.05f, 0, 0.72f, Material::kWood);
  }
  b.sphere("table_ball", 6.7f, 2.2f, 0.88f, 0.12f, Material::kBall);
  b.box("table_books", 7.0f, 7.3f, 2.6f, 2.85f, 0.76f, 0.90f, Material::kBook);
  b.cylinder("table_vase", 6.9f, 2.95f, 0.07f, 0.76f, 1.06f, Material::kPot);
  b.box("stool_seat", 5.9f, 6.25f, 2.3f, 2.7f, 0, 0.45f, Material::kLightWood);
  b.box("stool_back", 5.9f, 5.95f, 2.3f, 2.7f, 0.45f, 0.9f, Material::kLightWood);

  // Bookcase against the north wall: sides, top, plinth, two shelves, books, a globe on top.
  const float by0 = 5.6f, by1 = kWidthY;
  b.box("bookcase_left", 2.4f, 2.44f, by0, by1, 0, 1.9f, Material::kLightWood);
  b.box("bookcase_right", 4.16f, 4.2f, by0, by1, 0, 1.9f, Material::kLightWood);
  b.box("bookcase_top", 2.4f, 4.2f, by0, by1, 1.86f, 1.9f, Material::kLightWood);
  b.box("bookcase_plinth", 2.44f, 4.16f, by0, by1, 0, 0.08f, Material::kLightWood);
  b.box("bookcase_shelf_1", 2.44f, 4.16f, by0, by1, 0.60f, 0.63f, Material::kLightWood);
  b.box("bookcase_shelf_2", 2.44f, 4.16f, by0, by1, 1.20f, 1.23f, Material::kLightWood);
  b.box("books_1", 2.5f, 2.9f, 5.68f, by1, 0.08f, 0.38f, Material::kBook);
  b.box("books_2", 3.3f, 3.55f, 5.7f, by1, 0.08f, 0.34f, Material::kBook);
  b.box("books_3", 2.6f, 3.2f, 5.66f, by1, 0.63f, 0.89f, Material::kBook);
  b.box("books_4", 3.6f, 4.1f, 5.7f, by1, 0.63f, 0.85f, Material::kBook);
  b.box("books_5", 2.45f, 2.8f, 5.68f, by1, 1.23f, 1.51f, Material::kBook);
  b.box("books_6", 3.0f, 3.9f, 5.72f, by1, 1.23f, 1.43f, Material::kBook);
  b.sphere("globe", 3.9f, 5.8f, 2.05f, 0.15f, Material::kBall);

  // Plant in the north-west corner, armchair in the north-east corner.
  b.cylinder("plant_pot", 0.55f, 5.45f, 0.22f, 0, 0.5f, Material::kPot);
  b.sphere("plant", 0.55f, 5.45f, 0.88f, 0.38f, Material::kFoliage);
  b.box("armchair_seat", 6.6f, 7.5f, 5.05f, 5.85f, 0, 0.42f, Material::kFabric);
  b.box("armchair_back", 6.6f, 7.5f, 5.85f, kWidthY, 0, 0.95f, Material::kFabric);

  // Sofa against the west wall with a cushion, a low table in front of it.
  b.box("sofa_base", 0, 0.95f, 1.6f, 3.9f, 0, 0.42f, Material::kFabric);
  b.box("sofa_back", 0, 0.22f, 1.6f, 3.9f, 0.42f, 0.85f, Material::kFabric);
  b.box("sofa_arm_south", 0.22f, 0.95f, 1.6f, 1.8f, 0.42f, 0.62f, Material::kFabric);
  b.box("sofa_arm_north", 0.22f, 0.95f, 3.7f, 3.9f, 0.42f, 0.62f, Material::kFabric);
  b.sphere("sofa_cushion", 0.35f, 1.93f, 0.55f, 0.13f, Material::kBall);
  b.box("low_table", 1.3f, 1.9f, 2.3f, 3.2f, 0, 0.4f, Material::kWood);

  // Sideboard against the south wall with a lamp and a box; moving boxes and a bin in the
  // south-west corner.
  b.box("sideboard", 2.6f, 5.0f, 0, 0.45f, 0, 0.8f, Material::kPainted);
  b.cylinder("lamp", 4.6f, 0.22f, 0.08f, 0.8f, 1.2f, Material::kMetal);
  b.box("sideboard_box", 3.0f, 3.3f, 0.1f, 0.3f, 0.8f, 0.95f, Material::kCardboard);
  b.box("boxes_low", 1.2f, 1.7f, 0.1f, 0.6f, 0, 0.4f, Material::kCardboard);
  b.box("boxes_high", 1.3f, 1.65f, 0.15f, 0.5f, 0.4f, 0.7f, Material::kCardboard);
  b.cylinder("bin", 0.5f, 0.5f, 0.18f, 0, 0.45f, Material::kMetal);
  return room;
}

}  // namespace vf::synth
