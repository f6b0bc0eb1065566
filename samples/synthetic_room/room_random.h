#pragma once
// Counter-based random numbers: every value is a pure function of (seed, frame, pixel, ...), so a
// frame renders the same whichever thread loads it and in whatever order (FrameSource::load is
// random access, and writeTumFolder loads frames in parallel). No std:: distributions, whose
// output differs between standard libraries.
#include <cmath>
#include <cstdint>

namespace vf::synth {

inline uint64_t splitmix64(uint64_t x) {
  x += 0x9E3779B97F4A7C15ull;
  x = (x ^ (x >> 30)) * 0xBF58476D1CE4E5B9ull;
  x = (x ^ (x >> 27)) * 0x94D049BB133111EBull;
  return x ^ (x >> 31);
}

inline uint64_t hashCombine(uint64_t a, uint64_t b) { return splitmix64(a ^ (splitmix64(b) + 0x632BE59BD9B4E019ull)); }

inline uint64_t hash4(uint64_t a, uint64_t b, uint64_t c, uint64_t d) {
  return hashCombine(hashCombine(hashCombine(splitmix64(a), b), c), d);
}

// Uniform in [0, 1) from the top 24 bits (exact in a float).
inline float unitFloat(uint64_t h) { return float(h >> 40) * (1.0f / 16777216.0f); }

// A cheap 32-bit integer hash (murmur3's finaliser) for texture lattices, where splitmix64
// chains cost a sixth of the frame time.
inline uint32_t fmix32(uint32_t h) {
  h ^= h >> 16;
  h *= 0x85EBCA6Bu;
  h ^= h >> 13;
  h *= 0xC2B2AE35u;
  h ^= h >> 16;
  return h;
}
inline float latticeValue(int32_t i, int32_t j, uint32_t salt) {
  return float(fmix32(uint32_t(i) * 0x8DA6B343u ^ uint32_t(j) * 0xD8163841u ^ salt * 0xCB1AB31Fu) >> 8) *
         (1.0f / 16777216.0f);
}

// Roughly standard normal from 16 bits (the sum of two bytes, triangular, scaled to unit
// variance), for colour noise, whose exact shape does not matter.
inline float roughGaussian(uint32_t bits16) {
  return (float(bits16 & 0xFFu) + float((bits16 >> 8) & 0xFFu) - 255.f) * (1.f / 104.5f);
}

// Standard normal from one hash (Box-Muller on its two halves).
inline float gaussian(uint64_t h) {
  const float u1 = (float(h >> 40) + 0.5f) * (1.0f / 16777216.0f);  // (0, 1)
  const float u2 = float((h >> 8) & 0xFFFFFFull) * (1.0f / 16777216.0f);
  return std::sqrt(-2.f * std::log(u1)) * std::cos(2.f * float(M_PI) * u2);
}

}  // namespace vf::synth
