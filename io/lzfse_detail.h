#pragma once
// Internals shared by the LZFSE and LZVN block decoders: the output window and bounds-checked
// copy helpers. Not part of the public API (see io/lzfse.h).
#include <cstddef>
#include <cstdint>
#include <cstring>
#include <string>

#include "core/error.h"

namespace vf::lzfse_detail {

[[noreturn]] inline void fail(const std::string& what) { throw Error("LZFSE: " + what); }

inline uint32_t load32(const uint8_t* p) {
  return uint32_t(p[0]) | uint32_t(p[1]) << 8 | uint32_t(p[2]) << 16 | uint32_t(p[3]) << 24;
}
inline uint64_t load64(const uint8_t* p) {
  return uint64_t(load32(p)) | uint64_t(load32(p + 4)) << 32;
}

// The decoded stream so far. Matches may reach back into earlier blocks, so distances are checked
// against `pos` (bytes written since the start of the stream), never against the block start.
struct Output {
  uint8_t* data = nullptr;
  size_t pos = 0;       // bytes decoded
  size_t capacity = 0;  // writable bytes at data; copies may scribble up to here past pos
};

// Room needed past the end of a copy before the fast (16-byte step) path may be taken.
constexpr size_t kWildCopySlack = 32;

// Appends `len` bytes from `src` (src must have 16 readable bytes past len when `wild`).
inline void copyLiterals(uint8_t* dst, const uint8_t* src, size_t len, bool wild) {
  if (wild) {
    for (size_t i = 0; i < len; i += 16) std::memcpy(dst + i, src + i, 16);
  } else {
    std::memcpy(dst, src, len);
  }
}

// Copies a match of `len` bytes starting `dist` bytes back (dist >= 1, overlap allowed: dist < len
// repeats the last dist bytes, as LZ77 requires).
inline void copyMatch(uint8_t* dst, size_t dist, size_t len, bool wild) {
  const uint8_t* from = dst - dist;
  if (wild && dist >= 16) {
    for (size_t i = 0; i < len; i += 16) std::memcpy(dst + i, from + i, 16);
  } else if (wild && dist >= 8) {
    for (size_t i = 0; i < len; i += 8) std::memcpy(dst + i, from + i, 8);
  } else if (wild) {
    // Short period (runs of equal floats or bytes): the output repeats every `dist` bytes, so it
    // also repeats every multiple of it. After eff - dist single bytes, 8-byte steps from eff
    // bytes back (eff = the first multiple of dist >= 8) read only bytes already written.
    const size_t eff = dist * ((8 + dist - 1) / dist);
    size_t i = 0;
    for (; i < eff - dist && i < len; ++i) dst[i] = from[i];
    for (; i < len; i += 8) std::memcpy(dst + i, dst + i - eff, 8);
  } else if (dist >= len) {
    std::memcpy(dst, from, len);
  } else {
    for (size_t i = 0; i < len; ++i) dst[i] = from[i];
  }
}

}  // namespace vf::lzfse_detail
