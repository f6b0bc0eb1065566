#include "scene_builder.h"

namespace vf::synth {

void SceneBuilder::box(const std::string& name, float x0, float x1, float y0, float y1, float z0, float z1, Material m) {
  Primitive p;
  p.kind = Primitive::Kind::kBox;
  p.lo = Vec3(x0, y0, z0);
  p.hi = Vec3(x1, y1, z1);
  p.material = m;
  p.variant = next_variant++;
  p.name = name;
  room.primitives.push_back(p);
}

void SceneBuilder::sphere(const std::string& name, float x, float y, float z, float r, Material m) {
  Primitive p;
  p.kind = Primitive::Kind::kSphere;
  p.center = Vec3(x, y, z);
  p.radius = r;
  p.lo = p.center - Vec3::Constant(r);
  p.hi = p.center + Vec3::Constant(r);
  p.material = m;
  p.variant = next_variant++;
  p.name = name;
  room.primitives.push_back(p);
}

void SceneBuilder::cylinder(const std::string& name, float x, float y, float r, float z0, float z1, Material m) {
  Primitive p;
  p.kind = Primitive::Kind::kCylinder;
  p.center = Vec3(x, y, 0.5f * (z0 + z1));
  p.radius = r;
  p.lo = Vec3(x - r, y - r, z0);
  p.hi = Vec3(x + r, y + r, z1);
  p.material = m;
  p.variant = next_variant++;
  p.name = name;
  room.primitives.push_back(p);
}

void SceneBuilder::shell(const Vec3& lo, const Vec3& hi, Material m) {
  Primitive p;
  p.kind = Primitive::Kind::kShell;
  p.lo = lo;
  p.hi = hi;
  p.material = m;
  p.variant = next_variant++;
  p.name = "shell";
  room.primitives.push_back(p);
}

void SceneBuilder::wall(const std::string& name, bool along_x, float a0, float a1, float b0, float b1,
                        const std::vector<Opening>& openings, Material material) {
  int piece = 0;
  auto slab = [&](float s0, float s1, float z0, float z1) {
    if (s1 - s0 <= 0 || z1 - z0 <= 0) return;
    const std::string n = name + "_" + std::to_string(piece++);
    if (along_x) box(n, s0, s1, b0, b1, z0, z1, material);
    else box(n, b0, b1, s0, s1, z0, z1, material);
  };
  float cursor = a0;
  for (const Opening& o : openings) {
    slab(cursor, o.s0, 0, height_m);
    slab(o.s0, o.s1, 0, o.z0);
    slab(o.s0, o.s1, o.z1, height_m);
    cursor = o.s1;
  }
  slab(cursor, a1, 0, height_m);
}

}  // namespace vf::synth
