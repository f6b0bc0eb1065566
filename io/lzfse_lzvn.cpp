#include "io/lzfse_lzvn.h"

#include <array>
#include <string>

namespace vf::lzfse_detail {
namespace {

// LZVN opcodes (L = literal count copied after the opcode, M = match length, D = distance):
//   small distance   LLMMMDDD DDDDDDDD            L 0..3, M 3..10, D 11 bits
//   medium distance  101LLMMM DDDDDDMM DDDDDDDD   L 0..3, M 3..34, D 14 bits
//   large distance   LLMMM111 DDDDDDDD DDDDDDDD   L 0..3, M 3..10, D 16 bits
//   previous dist.   LLMMM110                     L 1..3, M 3..10, D = previous D
//   small match      1111MMMM                     M 1..15, D = previous D
//   large match      11110000 MMMMMMMM            M 16..271
//   small literal    1110LLLL                     L 1..15
//   large literal    11100000 LLLLLLLL            L 16..271
//   nop              00001110, 00010110
//   end of stream    00000110 + 7 padding bytes
//   undefined        0111xxxx, 1101xxxx, 00011110, 00100110, 00101110, 00110110, 00111110
enum class Op : uint8_t { kSmallD, kMediumD, kLargeD, kPrevD, kSmallM, kLargeM, kSmallL, kLargeL,
                          kNop, kEos, kUndefined };

constexpr Op classify(unsigned opc) {
  if (opc == 0x06) return Op::kEos;
  if (opc == 0x0e || opc == 0x16) return Op::kNop;
  if ((opc & 0xf0) == 0x70 || (opc & 0xf0) == 0xd0) return Op::kUndefined;
  if (opc == 0xe0) return Op::kLargeL;
  if ((opc & 0xf0) == 0xe0) return Op::kSmallL;
  if (opc == 0xf0) return Op::kLargeM;
  if ((opc & 0xf0) == 0xf0) return Op::kSmallM;
  if ((opc & 0xe0) == 0xa0) return Op::kMediumD;
  if ((opc & 7) == 7) return Op::kLargeD;
  if ((opc & 7) == 6) return opc < 0x40 ? Op::kUndefined : Op::kPrevD;  // L = 0 forms unused
  return Op::kSmallD;
}

constexpr std::array<Op, 256> makeOpTable() {
  std::array<Op, 256> t{};
  for (unsigned i = 0; i < 256; ++i) t[i] = classify(i);
  return t;
}
constexpr std::array<Op, 256> kOps = makeOpTable();

}  // namespace

void decodeLzvnBlock(const uint8_t* src, size_t src_size, size_t n_raw_bytes, Output& out) {
  const uint8_t* p = src;
  const uint8_t* const end = src + src_size;
  const size_t block_end = out.pos + n_raw_bytes;
  size_t d_prev = 0;  // no previous distance at block start: a repeat-distance opcode fails
  auto need = [&](size_t n) {
    if (size_t(end - p) < n) fail("LZVN payload truncated");
  };
  for (;;) {
    need(1);
    const unsigned opc = p[0];
    size_t L = 0, M = 0, D = d_prev;
    switch (kOps[opc]) {
      case Op::kSmallD:
        need(2);
        L = opc >> 6;
        M = ((opc >> 3) & 7) + 3;
        D = size_t(opc & 7) << 8 | p[1];
        p += 2;
        break;
      case Op::kMediumD: {
        need(3);
        const unsigned w = unsigned(p[1]) | unsigned(p[2]) << 8;
        L = (opc >> 3) & 3;
        M = ((opc & 7) << 2 | (w & 3)) + 3;
        D = w >> 2;
        p += 3;
        break;
      }
      case Op::kLargeD:
        need(3);
        L = opc >> 6;
        M = ((opc >> 3) & 7) + 3;
        D = size_t(p[1]) | size_t(p[2]) << 8;
        p += 3;
        break;
      case Op::kPrevD:
        L = opc >> 6;
        M = ((opc >> 3) & 7) + 3;
        p += 1;
        break;
      case Op::kSmallM:
        M = opc & 15;
        p += 1;
        break;
      case Op::kLargeM:
        need(2);
        M = size_t(p[1]) + 16;
        p += 2;
        break;
      case Op::kSmallL:
        L = opc & 15;
        p += 1;
        break;
      case Op::kLargeL:
        need(2);
        L = size_t(p[1]) + 16;
        p += 2;
        break;
      case Op::kNop:
        p += 1;
        continue;
      case Op::kEos:
        need(8);
        if (out.pos != block_end)
          fail("LZVN block ends after " + std::to_string(n_raw_bytes - (block_end - out.pos)) +
               " of " + std::to_string(n_raw_bytes) + " bytes");
        return;
      case Op::kUndefined:
        fail("LZVN undefined opcode " + std::to_string(opc));
    }
    if (L + M > block_end - out.pos) fail("LZVN block writes past its declared size");
    if (L) {
      need(L);
      std::memcpy(out.data + out.pos, p, L);
      p += L;
      out.pos += L;
    }
    if (M) {
      if (D == 0 || D > out.pos) fail("LZVN match distance " + std::to_string(D) + " out of range");
      const bool wild = out.capacity - out.pos >= M + kWildCopySlack;
      copyMatch(out.data + out.pos, D, M, wild);
      out.pos += M;
      d_prev = D;
    }
  }
}

}  // namespace vf::lzfse_detail
