#include "room_texture.h"

#include <algorithm>
#include <cmath>

#include "room_random.h"

namespace vf::synth {
namespace {

float lattice(int64_t i, int64_t j, uint64_t salt) { return latticeValue(int32_t(i), int32_t(j), uint32_t(salt)); }

float smooth(float t) { return t * t * (3.f - 2.f * t); }

// Value noise in [0, 1] with unit lattice spacing.
float valueNoise(float u, float v, uint64_t salt) {
  const float fu = std::floor(u), fv = std::floor(v);
  const int64_t i = int64_t(fu), j = int64_t(fv);
  const float a = smooth(u - fu), b = smooth(v - fv);
  const float n00 = lattice(i, j, salt), n10 = lattice(i + 1, j, salt);
  const float n01 = lattice(i, j + 1, salt), n11 = lattice(i + 1, j + 1, salt);
  return (n00 * (1 - a) + n10 * a) * (1 - b) + (n01 * (1 - a) + n11 * a) * b;
}

// Two octaves: `scale_m` and a third of it.
float fbm(float u, float v, float scale_m, uint64_t salt) {
  return 0.65f * valueNoise(u / scale_m, v / scale_m, salt) + 0.35f * valueNoise(3.f * u / scale_m, 3.f * v / scale_m, salt + 1);
}

// Plane coordinates of a face: the two axes other than the normal's dominant one.
void faceCoords(const Vec3& x, const Vec3& n, float& u, float& v) {
  const Vec3 a = n.cwiseAbs();
  if (a.z() >= a.x() && a.z() >= a.y()) { u = x.x(); v = x.y(); }
  else if (a.x() >= a.y()) { u = x.y(); v = x.z(); }
  else { u = x.x(); v = x.z(); }
}

Vec3 hueColor(float h, float saturation, float value) {
  h = h - std::floor(h);
  const float r = std::clamp(std::abs(h * 6 - 3) - 1, 0.f, 1.f);
  const float g = std::clamp(2 - std::abs(h * 6 - 2), 0.f, 1.f);
  const float b = std::clamp(2 - std::abs(h * 6 - 4), 0.f, 1.f);
  const Vec3 rgb(r, g, b);
  return 255.f * value * (Vec3::Constant(1.f - saturation) + saturation * rgb);
}

Vec3 wood(float along, float across, const Vec3& base, uint64_t salt) {
  const float grain = valueNoise(along * 2.f, across * 40.f, salt);  // long streaks
  const float blotch = fbm(along, across, 0.15f, salt + 5);
  return base * (0.78f + 0.25f * grain + 0.2f * blotch);
}

Vec3 floorColor(float x, float y) {
  const float plank_w = 0.18f, plank_l = 1.2f;
  const float row = std::floor(y / plank_w);
  const float offset = latticeValue(int32_t(row), 3, 1) * plank_l;
  const float col = std::floor((x + offset) / plank_l);
  const float fy = y / plank_w - row, fx = (x + offset) / plank_l - col;
  if (fy < 0.06f || fx < 0.01f) return Vec3(70, 45, 28);  // the 1 cm gaps between planks
  const float tone = 0.8f + 0.4f * latticeValue(int32_t(row), int32_t(col), 11);
  return wood(x, y, Vec3(165, 115, 70) * tone, 21);
}

Vec3 brickColor(float u, float v) {
  const float bh = 0.075f, bw = 0.25f;
  const float row = std::floor(v / bh);
  const float shifted = u / bw + 0.5f * std::fmod(std::abs(row), 2.f);
  const float col = std::floor(shifted);
  if (v / bh - row < 0.14f || shifted - col < 0.05f) return Vec3(200, 195, 185);  // mortar
  const float tone = 0.75f + 0.45f * latticeValue(int32_t(row), int32_t(col), 5);
  return Vec3(170, 75, 50) * tone;
}

// Low-contrast paint: a pale tint per facing direction (as light falls differently on each),
// +-2.5 % mottling at 80 cm and +-1.5 levels of fine grain. Against 2 levels of colour noise
// this is about as much as a real painted corridor wall gives the photometric term.
Vec3 corridorPaint(float u, float v, const Vec3& n) {
  const float shade = n.x() > 0.5f ? 1.0f : n.x() < -0.5f ? 0.97f : n.y() > 0.5f ? 0.985f : 0.955f;
  const Vec3 base = Vec3(208, 204, 192) * shade;
  return base * (0.96f + 0.05f * fbm(u, v, 0.8f, 61)) + Vec3::Constant(3.f * (valueNoise(u / 0.04f, v / 0.04f, 62) - 0.5f));
}

Vec3 corridorShellColor(float u, float v, const Vec3& n) {
  if (n.z() > 0.5f)  // linoleum: grey-blue, mottled at 1 m, speckled at 1.5 cm (+-4 levels)
    return Vec3(150, 155, 162) * (0.93f + 0.08f * fbm(u, v, 1.0f, 63)) +
           Vec3::Constant(8.f * (valueNoise(u / 0.015f, v / 0.015f, 64) - 0.5f));
  if (n.z() < -0.5f) return Vec3(236, 235, 230) * (0.97f + 0.03f * fbm(u, v, 1.0f, 65));  // ceiling
  return corridorPaint(u, v, n);  // the backs of recesses and of the window niche
}

}  // namespace

Vec3 surfaceColor(const Primitive& p, const Vec3& x, const Vec3& n) {
  float u, v;
  faceCoords(x, n, u, v);
  const uint64_t salt = uint64_t(p.variant) * 131u + 7u;
  const float vary = latticeValue(p.variant, 1, 2);  // one number per primitive
  Vec3 c = Vec3::Zero();
  switch (p.material) {
    case Material::kShell: {  // floor, ceiling, niche backs by the normal
      if (n.z() > 0.5f) c = floorColor(x.x(), x.y());
      else if (n.z() < -0.5f) c = Vec3(235, 232, 225) * (0.85f + 0.15f * fbm(u, v, 0.4f, salt));
      else c = brickColor(u, v);
      break;
    }
    case Material::kWall: {
      // Painted plaster, one tint per wall piece, mottled at 30 cm with a finer 6 cm texture, and
      // a dado stripe at 0.9-1.0 m that ties the pieces of one wall together.
      const int face = n.x() > 0.5f ? 0 : n.x() < -0.5f ? 1 : n.y() > 0.5f ? 2 : n.y() < -0.5f ? 3 : 4;
      const Vec3 tint = hueColor(0.08f + 0.21f * float(face), 0.25f, 0.9f);
      c = tint * (0.72f + 0.2f * fbm(u, v, 0.3f, 41) + 0.12f * valueNoise(u / 0.06f, v / 0.06f, 43));
      if (x.z() > 0.9f && x.z() < 1.0f) c = Vec3(120, 140, 160) * (0.8f + 0.3f * valueNoise(u / 0.05f, 0, 44));
      break;
    }
    case Material::kDoor: {
      c = wood(x.z(), x.x(), Vec3(130, 80, 45), salt);
      const float dx = std::min(std::abs(x.x() - 6.2f), std::abs(x.x() - 7.1f));
      if (dx > 0.1f && dx < 0.13f) c *= 0.6f;  // panel edges
      if (std::abs(x.z() - 1.0f) < 0.015f || std::abs(x.z() - 1.9f) < 0.015f) c *= 0.6f;
      break;
    }
    case Material::kWood: c = wood(u, v, Vec3(120, 72, 40), salt); break;
    case Material::kLightWood: c = wood(u + v, u - v, Vec3(205, 170, 120), salt); break;
    case Material::kFabric:
      c = hueColor(0.6f, 0.45f, 0.55f) * (0.75f + 0.35f * fbm(u, v, 0.05f, salt)) +
          Vec3::Constant(30.f * float(std::fmod(std::floor(u / 0.12f) + std::floor(v / 0.12f), 2.0f)));
      break;
    case Material::kBook: {
      // Spines 1-7 cm wide (band edges jittered about a 4 cm grid) in random hue, saturation and
      // brightness. Equal widths at equal brightness made a grating the photometric term aligned
      // one spine off, 3.5 cm per frame along the bookcase.
      const float s_m = std::abs(n.x()) > 0.5f ? x.y() : x.x();
      const float cell = std::floor(s_m / 0.04f);
      const float edge = (cell + 0.5f + 0.75f * (latticeValue(int32_t(cell), int32_t(salt), 8) - 0.5f)) * 0.04f;
      const int32_t band = int32_t(cell) - (s_m < edge ? 1 : 0);  // a spine runs from one edge to the next
      c = hueColor(latticeValue(band, int32_t(salt), 9), 0.35f + 0.55f * latticeValue(band, int32_t(salt), 10),
                   0.3f + 0.65f * latticeValue(band, int32_t(salt), 12));
      if (std::abs(x.z() - 0.5f * (p.lo.z() + p.hi.z())) < 0.012f) c = Vec3(230, 220, 190);  // titles
      break;
    }
    case Material::kPicture:
      c = hueColor(1.5f * fbm(u, v, 0.25f, salt) + vary, 0.8f, 0.45f + 0.5f * valueNoise(u / 0.08f, v / 0.08f, salt + 3));
      break;
    case Material::kPainted: {
      c = Vec3(215, 215, 205) * (0.85f + 0.15f * fbm(u, v, 0.2f, salt));
      const float drawer = std::fmod(x.z(), 0.27f);
      if (drawer < 0.015f) c *= 0.45f;  // drawer gaps
      if (std::abs(std::fmod(x.x(), 0.6f) - 0.3f) < 0.04f && std::abs(drawer - 0.15f) < 0.02f) c = Vec3(40, 40, 45);
      break;
    }
    case Material::kCardboard: {
      c = Vec3(185, 145, 95) * (0.85f + 0.25f * fbm(u, v, 0.1f, salt));
      if (std::abs(v - 0.5f * (p.lo.z() + p.hi.z())) < 0.025f) c = Vec3(200, 190, 160);  // tape
      break;
    }
    case Material::kBall: {
      // Six coloured segments around the vertical axis, latitude bands.
      const Vec3 d = (x - p.center).normalized();
      const float seg = std::floor((std::atan2(d.y(), d.x()) + float(M_PI)) / float(M_PI / 3));
      c = hueColor(seg / 6.f + vary, 0.75f, d.z() > 0.3f ? 0.9f : 0.6f);
      break;
    }
    case Material::kPot: {
      c = Vec3(180, 90, 55) * (0.85f + 0.2f * valueNoise(x.x() / 0.05f + x.y() / 0.05f, x.z() / 0.05f, salt));
      if (std::fmod(x.z(), 0.12f) < 0.02f) c *= 0.6f;  // bands
      break;
    }
    case Material::kFoliage: {
      const Vec3 d = x - p.center;
      const float leaf = 0.5f * valueNoise(d.x() / 0.04f + d.z() / 0.07f, d.y() / 0.04f - d.z() / 0.05f, salt) +
                         0.5f * valueNoise(d.y() / 0.1f, d.z() / 0.1f, salt + 1);
      c = Vec3(50, 120, 45) * (0.5f + 0.9f * leaf);
      break;
    }
    case Material::kMetal: {
      const float a = std::atan2(x.y() - p.center.y(), x.x() - p.center.x());
      c = Vec3(150, 155, 165) * (0.7f + 0.3f * valueNoise(a * 3.f, x.z() / 0.04f, salt) + 0.1f * std::abs(n.z()));
      break;
    }
    case Material::kCorridorShell: c = corridorShellColor(u, v, n); break;
    case Material::kCorridorWall: c = corridorPaint(u, v, n); break;
    case Material::kTrim:  // gloss white door frames and light fittings
      c = Vec3(238, 236, 230) * (0.97f + 0.03f * valueNoise(u / 0.1f, v / 0.1f, salt));
      break;
    case Material::kRadiator:  // white, with the shadows between its fins every 5 cm
      c = Vec3(225, 225, 220) * (std::fmod(std::abs(u), 0.05f) < 0.012f ? 0.72f : 1.f);
      break;
    case Material::kExtinguisher: {  // red, with a white label
      c = Vec3(190, 30, 25) * (0.9f + 0.15f * valueNoise(x.z() / 0.05f, 0, salt));
      const float h = (x.z() - p.lo.z()) / (p.hi.z() - p.lo.z());
      if (h > 0.35f && h < 0.65f) c = Vec3(230, 228, 220) * (0.85f + 0.15f * valueNoise(u / 0.01f, v / 0.01f, salt));
      break;
    }
  }
  return c.cwiseMax(0.f).cwiseMin(255.f);
}

}  // namespace vf::synth
