#pragma once
// Finite-state-entropy (tANS) pieces of LZFSE: the backward bit reader and the decoding tables.
//
// An FSE payload is written forwards by the encoder and read backwards by the decoder, starting
// from the payload end. The reader keeps 56..63 bits in a 64-bit accumulator and takes bits from
// its top. A block header stores the bit count of the last, partial byte as -7..0.
//
// Table layout (shared with the encoder): states are handed out to symbols in symbol order, a
// symbol of frequency f owning f consecutive states. With N states and k = clz(f) - clz(N)
// (so that N <= f << k < 2N), the first j0 = (2N >> k) - f of its states read k bits and the rest
// read k - 1 bits; the next state is delta + the bits read.
#include <cstddef>
#include <cstdint>
#include <cstring>

#include "io/lzfse_detail.h"

namespace vf::lzfse_detail {

class BackwardBitReader {
 public:
  // Reads backwards from `end` towards `begin`; `hard_end` bounds the 8-byte refill loads (the end
  // of the whole input, which may lie past `end`).
  BackwardBitReader(const uint8_t* begin, const uint8_t* end, const uint8_t* hard_end,
                    int final_bits, const char* what)
      : begin_(begin), avail_(size_t(end - begin)), hard_end_(hard_end), what_(what) {
    if (final_bits < -7 || final_bits > 0) fail(std::string(what) + " bit count out of range");
    accum_ = load(final_bits != 0 ? 8 : 7);
    nbits_ = (final_bits != 0 ? 64 : 56) + final_bits;
    // The encoder zeroes the bits above the partial byte; anything there is corruption.
    if ((accum_ >> nbits_) != 0) fail(std::string(what) + " stream start bits are not zero");
  }

  // Brings the accumulator back to 56..63 bits (whole bytes only).
  inline void refill() {
    const int nbytes = (63 - nbits_) >> 3;
    if (nbytes == 0) return;
    const int nbits = nbytes * 8;
    accum_ = (accum_ << nbits) | load(size_t(nbytes));
    nbits_ += nbits;
  }

  // Takes the top n bits (n <= bits held; callers pull at most 54 bits between refills).
  inline uint32_t pull(int n) {
    nbits_ -= n;
    const uint64_t result = accum_ >> nbits_;
    accum_ &= (uint64_t(1) << nbits_) - 1;
    return uint32_t(result);
  }

 private:
  // The next n (<= 8) bytes below the read position, as a little-endian integer. The reference
  // decoder lets the last refills of a payload load bytes that precede it (header or the other
  // payload); a valid stream never consumes those bits, so they read as zeros here, and a stream
  // that needs more than 8 of them is truncated.
  inline uint64_t load(size_t n) {
    if (n <= avail_) {
      avail_ -= n;
      const uint8_t* p = begin_ + avail_;
      if (size_t(hard_end_ - p) >= 8) {
        uint64_t v;
        std::memcpy(&v, p, 8);  // little-endian hosts only (x86-64, arm64)
        return n == 8 ? v : v & ((uint64_t(1) << (8 * n)) - 1);
      }
      uint64_t v = 0;
      for (size_t i = 0; i < n; ++i) v |= uint64_t(p[i]) << (8 * i);
      return v;
    }
    underrun_ += n - avail_;
    if (underrun_ > 8) fail(std::string(what_) + " payload truncated");
    uint64_t v = 0;
    const size_t shift = n - avail_;
    for (size_t i = 0; i < avail_; ++i) v |= uint64_t(begin_[i]) << (8 * (i + shift));
    avail_ = 0;
    return v;
  }

  const uint8_t* begin_;
  size_t avail_;  // unread payload bytes at begin_
  const uint8_t* hard_end_;
  const char* what_;
  size_t underrun_ = 0;
  uint64_t accum_ = 0;
  int nbits_ = 0;
};

// Literal table entry packed as (delta << 16) | (symbol << 8) | k.
using LiteralEntry = int32_t;

inline uint8_t decodeLiteral(uint16_t& state, const LiteralEntry* table, BackwardBitReader& in) {
  const LiteralEntry e = table[state];
  state = uint16_t((e >> 16) + int32_t(in.pull(e & 0xff)));
  return uint8_t(e >> 8);
}

// L, M and D entries: the symbol stands for base + `value_bits` raw bits read with the state bits.
struct ValueEntry {
  uint8_t total_bits;  // state bits + value bits
  uint8_t value_bits;
  int16_t delta;
  int32_t base;
};

inline int32_t decodeValue(uint16_t& state, const ValueEntry* table, BackwardBitReader& in) {
  const ValueEntry e = table[state];
  const uint32_t bits = in.pull(e.total_bits);
  state = uint16_t(e.delta + int32_t(bits >> e.value_bits));
  return e.base + int32_t(bits & ((1u << e.value_bits) - 1));
}

// Visits every (state, symbol, k, delta) of a normalised frequency table; throws when the
// frequencies sum past nstates. States beyond the sum stay as the caller initialised them.
template <class Visit>
void forEachState(int nstates, int nsymbols, const uint16_t* freq, const char* what, Visit visit) {
  const int n_clz = __builtin_clz(unsigned(nstates));
  int state = 0;
  for (int s = 0; s < nsymbols; ++s) {
    const int f = freq[s];
    if (f == 0) continue;
    if (state + f > nstates) fail(std::string(what) + " frequencies exceed the state count");
    const int k = __builtin_clz(unsigned(f)) - n_clz;
    const int j0 = ((2 * nstates) >> k) - f;
    for (int j = 0; j < f; ++j, ++state) {
      if (j < j0) {
        visit(state, s, k, ((f + j) << k) - nstates);
      } else {
        visit(state, s, k - 1, (j - j0) << (k - 1));  // j >= j0 implies k >= 1
      }
    }
  }
}

inline void buildLiteralTable(const uint16_t* freq, LiteralEntry* table /*1024*/) {
  std::memset(table, 0, 1024 * sizeof(LiteralEntry));
  forEachState(1024, 256, freq, "literal", [&](int state, int symbol, int k, int delta) {
    table[state] = (delta << 16) | (symbol << 8) | k;
  });
}

inline void buildValueTable(int nstates, int nsymbols, const uint16_t* freq,
                            const uint8_t* extra_bits, const int32_t* base, const char* what,
                            ValueEntry* table) {
  std::memset(table, 0, size_t(nstates) * sizeof(ValueEntry));
  forEachState(nstates, nsymbols, freq, what, [&](int state, int symbol, int k, int delta) {
    table[state] = {uint8_t(k + extra_bits[symbol]), extra_bits[symbol], int16_t(delta),
                    base[symbol]};
  });
}

}  // namespace vf::lzfse_detail
