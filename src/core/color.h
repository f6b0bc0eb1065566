#pragma once
// sRGB <-> linear (IEC 61966-2-1), once for every writer and reader. Images, PLY bytes and OBJ
// vertex colours are sRGB; the scene's color grid, glTF's COLOR_0 and material factors are linear.
#include <algorithm>
#include <array>
#include <cmath>
#include <cstdint>

#include "core/math.h"

namespace vf {

inline float srgbToLinear(float s) {
  s = std::clamp(s, 0.f, 1.f);
  return s <= 0.04045f ? s / 12.92f : std::pow((s + 0.055f) / 1.055f, 2.4f);
}

inline float linearToSrgb(float x) {
  x = std::clamp(x, 0.f, 1.f);
  return x <= 0.0031308f ? 12.92f * x : 1.055f * std::pow(x, 1.f / 2.4f) - 0.055f;
}

// 8-bit sRGB -> linear 0..1 by table (exact for all 256 codes).
inline float srgb8ToLinear(uint8_t c) {
  static const std::array<float, 256> table = [] {
    std::array<float, 256> t{};
    for (int i = 0; i < 256; ++i) t[size_t(i)] = srgbToLinear(float(i) / 255.f);
    return t;
  }();
  return table[c];
}

// Linear 0..1 -> 8-bit sRGB through a 4096-entry table: a mesh converts millions of vertex
// channels and pow per channel is slow. Outside 0..1 clamps; NaN gives 0.
inline uint8_t linearToSrgb8(float x) {
  static const std::array<uint8_t, 4096> table = [] {
    std::array<uint8_t, 4096> t{};
    for (int i = 0; i < 4096; ++i) t[size_t(i)] = uint8_t(std::lround(linearToSrgb(float(i) / 4095.f) * 255.f));
    return t;
  }();
  if (!(x > 0.f)) return 0;
  return table[size_t(std::min(x, 1.f) * 4095.f + 0.5f)];
}

inline Rgb8 linearToSrgb8(Vec3f linear) {
  return {linearToSrgb8(linear.x), linearToSrgb8(linear.y), linearToSrgb8(linear.z), 255};
}
inline Vec3f srgb8ToLinear(Rgb8 c) { return {srgb8ToLinear(c.r), srgb8ToLinear(c.g), srgb8ToLinear(c.b)}; }

}  // namespace vf
