#pragma once
#include <cmath>
#include <cstdint>
#include <cstring>

#include "core/hd.h"

namespace vf {

// exp(x) for x <= 0 to ~1e-4 relative error, identical on host and device (the bilateral filter
// calls it 25 times per pixel; libm's expf would dominate the CPU stage and differ from __expf).
VF_HD float fastExp(float x) {
  if (x < -80.f) return 0.f;
  const float t = x * 1.44269504f;  // log2(e)
  const float fi = floorf(t);
  const float f = t - fi;
  // 2^f on [0, 1): minimax cubic-quartic polynomial
  const float p = 1.f + f * (0.69314718f + f * (0.24022650f + f * (0.05550411f + f * 0.00961813f)));
  const int e = int(fi) + 127;
  if (e <= 0) return 0.f;
  const uint32_t bits = uint32_t(e) << 23;
  float scale;
  memcpy(&scale, &bits, sizeof(scale));
  return p * scale;
}

// A quiet NaN, the same bits on host and device (marks "no value" that arithmetic carries along).
VF_HD float quietNaN() {
  const uint32_t bits = 0x7fc00000u;
  float f;
  memcpy(&f, &bits, sizeof(f));
  return f;
}

// min and max where the second operand is never NaN (a NaN first operand gives the second, as
// fminf / fmaxf do). libm's fminf / fmaxf must return the other operand for a NaN on either
// side, so without -ffinite-math-only GCC calls them instead of emitting one instruction, and a
// loop around such a call no longer vectorises (the brick marking made 13 such calls per pixel
// block, the raycast 7 per ray, the ICP's Huber weight one per lane, the colour downsample 4 per
// colour pixel).
VF_HD float minFloat(float a, float b) { return a < b ? a : b; }
VF_HD float maxFloat(float a, float b) { return a > b ? a : b; }

VF_HD int clampInt(int v, int lo, int hi) { return v < lo ? lo : (v > hi ? hi : v); }
VF_HD float clampFloat(float v, float lo, float hi) { return v < lo ? lo : (v > hi ? hi : v); }

}  // namespace vf
