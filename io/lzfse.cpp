// LZFSE stream and block decoding. Format notes (from Apple's public lzfse description):
//  - all integers little endian; blocks follow each other until "bvx$";
//  - an LZFSE block is header, literal payload, L/M/D payload. Literals are FSE-coded with four
//    interleaved states (1024 states, 256 symbols); each match is an (L, M, D) triple coded with
//    three FSE states (64, 64, 256 states) whose symbols stand for a base value plus extra raw bits.
//    D = 0 repeats the previous distance. Both payloads are read backwards (io/lzfse_fse.h).
#include "io/lzfse.h"

#include <algorithm>
#include <cstdio>
#include <string>

#include "io/lzfse_detail.h"
#include "io/lzfse_fse.h"
#include "io/lzfse_lzvn.h"

namespace vf {
namespace lzfse_detail {
namespace {

constexpr uint32_t kMagicEnd = 0x24787662;           // "bvx$"
constexpr uint32_t kMagicUncompressed = 0x2d787662;  // "bvx-"
constexpr uint32_t kMagicV1 = 0x31787662;            // "bvx1"
constexpr uint32_t kMagicV2 = 0x32787662;            // "bvx2"
constexpr uint32_t kMagicLzvn = 0x6e787662;          // "bvxn"

constexpr int kLStates = 64, kMStates = 64, kDStates = 256, kLiteralStates = 1024;
constexpr int kLSymbols = 20, kMSymbols = 20, kDSymbols = 64, kLiteralSymbols = 256;
constexpr int kFreqCount = kLSymbols + kMSymbols + kDSymbols + kLiteralSymbols;
constexpr uint32_t kMatchesPerBlock = 10000;
constexpr uint32_t kLiteralsPerBlock = 4 * kMatchesPerBlock;
constexpr size_t kMaxMatchLength = 2359;  // m_base[19] + 2^11 - 1
constexpr size_t kLiteralSlack = 64;      // decoded-literal buffer padding for 16-byte copies

constexpr uint8_t kLExtraBits[kLSymbols] = {0, 0, 0, 0, 0, 0, 0, 0, 0, 0,
                                            0, 0, 0, 0, 0, 0, 2, 3, 5, 8};
constexpr int32_t kLBase[kLSymbols] = {0,  1,  2,  3,  4,  5,  6,  7,  8,  9,
                                       10, 11, 12, 13, 14, 15, 16, 20, 28, 60};
constexpr uint8_t kMExtraBits[kMSymbols] = {0, 0, 0, 0, 0, 0, 0, 0, 0, 0,
                                            0, 0, 0, 0, 0, 0, 3, 5, 8, 11};
constexpr int32_t kMBase[kMSymbols] = {0,  1,  2,  3,  4,  5,  6,  7,  8,  9,
                                       10, 11, 12, 13, 14, 15, 16, 24, 56, 312};

// Distance symbols come in groups of four sharing an extra-bit count (i / 4); each base is the
// previous base plus the range of the previous symbol: 0 1 2 3 4 6 8 10 12 16 ... 229372.
struct DTables {
  uint8_t extra_bits[kDSymbols];
  int32_t base[kDSymbols];
};
constexpr DTables makeDTables() {
  DTables t{};
  int32_t base = 0;
  for (int i = 0; i < kDSymbols; ++i) {
    t.extra_bits[i] = uint8_t(i / 4);
    t.base[i] = base;
    base += int32_t(1) << (i / 4);
  }
  return t;
}
constexpr DTables kD = makeDTables();
static_assert(kD.base[5] == 6 && kD.base[13] == 36 && kD.base[63] == 229372, "LZFSE D table");

struct BlockHeader {
  uint32_t n_raw_bytes = 0;
  uint32_t n_literals = 0, n_matches = 0;
  uint32_t n_literal_payload_bytes = 0, n_lmd_payload_bytes = 0;
  int32_t literal_bits = 0, lmd_bits = 0;
  uint16_t literal_state[4] = {};
  uint16_t l_state = 0, m_state = 0, d_state = 0;
  uint16_t freq[kFreqCount] = {};  // L, M, D, literal tables back to back
  size_t header_size = 0;
};

// v1: the header struct stored as is: seven uint32 fields, int32 literal_bits, four uint16
// literal states, int32 lmd_bits, three uint16 L/M/D states (ends at byte 50), then 360 uint16
// frequencies; the C struct is padded to 772 bytes and the payload follows that.
constexpr size_t kV1HeaderSize = 772;

BlockHeader parseV1(const uint8_t* p, size_t avail) {
  if (avail < kV1HeaderSize) fail("v1 block header truncated");
  BlockHeader h;
  h.n_raw_bytes = load32(p + 4);
  const uint32_t n_payload = load32(p + 8);
  h.n_literals = load32(p + 12);
  h.n_matches = load32(p + 16);
  h.n_literal_payload_bytes = load32(p + 20);
  h.n_lmd_payload_bytes = load32(p + 24);
  h.literal_bits = int32_t(load32(p + 28));
  for (int i = 0; i < 4; ++i) h.literal_state[i] = uint16_t(p[32 + 2 * i] | p[33 + 2 * i] << 8);
  h.lmd_bits = int32_t(load32(p + 40));
  h.l_state = uint16_t(p[44] | p[45] << 8);
  h.m_state = uint16_t(p[46] | p[47] << 8);
  h.d_state = uint16_t(p[48] | p[49] << 8);
  for (int i = 0; i < kFreqCount; ++i) h.freq[i] = uint16_t(p[50 + 2 * i] | p[51 + 2 * i] << 8);
  if (uint64_t(h.n_literal_payload_bytes) + h.n_lmd_payload_bytes != n_payload)
    fail("v1 block header payload sizes disagree");
  h.header_size = kV1HeaderSize;
  return h;
}

// v2 frequency code: a prefix code read from the low bits. Values 0..7 take 2, 3 or 5 bits
// (table below), 8..23 take 8 bits (low nibble 0111 + 4-bit value - 8) and 24..1047 take 14 bits
// (low nibble 1111 + 10-bit value - 24).
int decodeFreq(uint32_t bits, int& nbits) {
  static constexpr int8_t kBits[32] = {2, 3, 2, 5, 2, 3, 2, 8, 2, 3, 2, 5, 2, 3, 2, 14,
                                       2, 3, 2, 5, 2, 3, 2, 8, 2, 3, 2, 5, 2, 3, 2, 14};
  static constexpr int8_t kValue[32] = {0, 2, 1, 4, 0, 3, 1, -1, 0, 2, 1, 5, 0, 3, 1, -1,
                                        0, 2, 1, 6, 0, 3, 1, -1, 0, 2, 1, 7, 0, 3, 1, -1};
  const uint32_t b = bits & 31;
  nbits = kBits[b];
  if (nbits == 8) return 8 + int((bits >> 4) & 0xf);
  if (nbits == 14) return 24 + int((bits >> 4) & 0x3ff);
  return kValue[b];
}

uint32_t field(uint64_t word, int offset, int nbits) {
  return uint32_t((word >> offset) & ((uint64_t(1) << nbits) - 1));
}

// v2: magic, n_raw_bytes, three packed 64-bit words, then the frequency tables (prefix coded)
// up to header_size bytes from the magic.
BlockHeader parseV2(const uint8_t* p, size_t avail) {
  if (avail < 32) fail("v2 block header truncated");
  BlockHeader h;
  h.n_raw_bytes = load32(p + 4);
  const uint64_t w0 = load64(p + 8), w1 = load64(p + 16), w2 = load64(p + 24);
  h.n_literals = field(w0, 0, 20);
  h.n_literal_payload_bytes = field(w0, 20, 20);
  h.n_matches = field(w0, 40, 20);
  h.literal_bits = int32_t(field(w0, 60, 3)) - 7;
  for (int i = 0; i < 4; ++i) h.literal_state[i] = uint16_t(field(w1, 10 * i, 10));
  h.n_lmd_payload_bytes = field(w1, 40, 20);
  h.lmd_bits = int32_t(field(w1, 60, 3)) - 7;
  h.header_size = field(w2, 0, 32);
  h.l_state = uint16_t(field(w2, 32, 10));
  h.m_state = uint16_t(field(w2, 42, 10));
  h.d_state = uint16_t(field(w2, 52, 10));
  if (h.header_size < 32 || h.header_size > avail)
    fail("v2 block header size " + std::to_string(h.header_size) + " out of range");
  const uint8_t* q = p + 32;
  const uint8_t* const q_end = p + h.header_size;
  if (q == q_end) return h;  // no frequency tables: every table is empty
  uint32_t accum = 0;
  int accum_bits = 0;
  for (int i = 0; i < kFreqCount; ++i) {
    while (q < q_end && accum_bits + 8 <= 32) {
      accum |= uint32_t(*q++) << accum_bits;
      accum_bits += 8;
    }
    int nbits = 0;
    const int value = decodeFreq(accum, nbits);
    if (nbits > accum_bits) fail("v2 frequency table truncated");
    h.freq[i] = uint16_t(value);
    accum >>= nbits;
    accum_bits -= nbits;
  }
  if (accum_bits >= 8 || q != q_end) fail("v2 frequency table size disagrees with header size");
  return h;
}

void validate(const BlockHeader& h) {
  if (h.n_literals > kLiteralsPerBlock) fail("block claims " + std::to_string(h.n_literals) + " literals");
  if (h.n_matches > kMatchesPerBlock) fail("block claims " + std::to_string(h.n_matches) + " matches");
  for (uint16_t s : h.literal_state)
    if (s >= kLiteralStates) fail("literal state out of range");
  if (h.l_state >= kLStates || h.m_state >= kMStates || h.d_state >= kDStates)
    fail("L/M/D state out of range");
  // Every byte of output comes from a literal or a match, so this bounds n_raw_bytes before
  // anything is allocated for it.
  if (h.n_raw_bytes > uint64_t(h.n_literals) + uint64_t(h.n_matches) * kMaxMatchLength)
    fail("block claims " + std::to_string(h.n_raw_bytes) + " bytes from " +
         std::to_string(h.n_literals) + " literals and " + std::to_string(h.n_matches) +
         " matches");
}

// Decodes the literal and L/M/D payloads of one LZFSE block, appending n_raw_bytes to out.
// `literals` must hold n_literals + kLiteralSlack bytes.
void decodeLzfseBlock(const BlockHeader& h, const uint8_t* payload, const uint8_t* input_end,
                      Output& out, uint8_t* literals) {
  LiteralEntry literal_table[kLiteralStates];
  ValueEntry l_table[kLStates], m_table[kMStates], d_table[kDStates];
  buildLiteralTable(h.freq + kLSymbols + kMSymbols + kDSymbols, literal_table);
  buildValueTable(kLStates, kLSymbols, h.freq, kLExtraBits, kLBase, "L", l_table);
  buildValueTable(kMStates, kMSymbols, h.freq + kLSymbols, kMExtraBits, kMBase, "M", m_table);
  buildValueTable(kDStates, kDSymbols, h.freq + kLSymbols + kMSymbols, kD.extra_bits, kD.base,
                  "D", d_table);

  // Literals: four interleaved states, n_literals is a multiple of 4 for the reference encoder
  // (rounded up here; the slack absorbs it).
  const uint8_t* lit_payload = payload;
  const uint8_t* lmd_payload = payload + h.n_literal_payload_bytes;
  {
    BackwardBitReader in(lit_payload, lmd_payload, input_end, h.literal_bits, "literal");
    uint16_t s0 = h.literal_state[0], s1 = h.literal_state[1], s2 = h.literal_state[2],
             s3 = h.literal_state[3];
    for (uint32_t i = 0; i < h.n_literals; i += 4) {
      in.refill();  // 4 x at most 10 bits
      literals[i + 0] = decodeLiteral(s0, literal_table, in);
      literals[i + 1] = decodeLiteral(s1, literal_table, in);
      literals[i + 2] = decodeLiteral(s2, literal_table, in);
      literals[i + 3] = decodeLiteral(s3, literal_table, in);
    }
  }

  BackwardBitReader in(lmd_payload, lmd_payload + h.n_lmd_payload_bytes, input_end, h.lmd_bits,
                       "L/M/D");
  uint16_t l_state = h.l_state, m_state = h.m_state, d_state = h.d_state;
  const uint8_t* lit = literals;
  const uint8_t* const lit_end = literals + h.n_literals;
  const size_t block_end = out.pos + h.n_raw_bytes;
  size_t D = 0;  // no distance yet: a leading "repeat distance" with a match is corrupt
  for (uint32_t i = 0; i < h.n_matches; ++i) {
    in.refill();  // L <= 14 bits, M <= 17 bits, D <= 23 bits: 54 <= 56 held after a refill
    const size_t L = size_t(decodeValue(l_state, l_table, in));
    const size_t M = size_t(decodeValue(m_state, m_table, in));
    const size_t new_d = size_t(decodeValue(d_state, d_table, in));
    if (new_d) D = new_d;
    if (L > size_t(lit_end - lit)) fail("match uses more literals than the block holds");
    if (L + M > block_end - out.pos) fail("block writes past its declared size");
    if (M && (D == 0 || D > out.pos + L))
      fail("match distance " + std::to_string(D) + " reaches before the stream start");
    uint8_t* dst = out.data + out.pos;
    const bool wild = out.capacity - out.pos >= L + M + kWildCopySlack;
    copyLiterals(dst, lit, L, wild);
    lit += L;
    if (M) copyMatch(dst + L, D, M, wild);
    out.pos += L + M;
  }
  if (out.pos != block_end)
    fail("block decoded to " + std::to_string(h.n_raw_bytes - (block_end - out.pos)) +
         " bytes, header says " + std::to_string(h.n_raw_bytes));
}

// Grows the output so that `need` more bytes (plus copy slack) fit; returns false if it cannot.
class OutputSink {
 public:
  virtual ~OutputSink() = default;
  virtual void reserveBlock(Output& out, size_t n_raw_bytes) = 0;
};

class VectorSink : public OutputSink {
 public:
  VectorSink(std::vector<uint8_t>& v, size_t max_bytes) : v_(v), max_(max_bytes) {}
  void reserveBlock(Output& out, size_t n) override {
    if (n > max_ || out.pos > max_ - n)
      fail("decoded size exceeds the limit of " + std::to_string(max_) + " bytes");
    const size_t want = out.pos + n + kWildCopySlack;
    if (v_.size() < want) v_.resize(std::max(want, std::min(max_, v_.size() * 2)));
    out.data = v_.data();
    out.capacity = v_.size();
  }

 private:
  std::vector<uint8_t>& v_;
  size_t max_;
};

class FixedSink : public OutputSink {
 public:
  void reserveBlock(Output& out, size_t n) override {
    if (n > out.capacity - out.pos)
      fail("decoded size exceeds the output buffer of " + std::to_string(out.capacity) + " bytes");
  }
};

void decodeStream(const uint8_t* src, size_t n, Output& out, OutputSink& sink) {
  if (!src && n) fail("null input");
  const uint8_t* p = src;
  const uint8_t* const end = src + n;
  std::vector<uint8_t> literals;
  for (;;) {
    const size_t avail = size_t(end - p);
    if (avail < 4) fail("stream truncated (no end-of-stream block)");
    const uint32_t magic = load32(p);
    if (magic == kMagicEnd) return;
    if (magic == kMagicUncompressed) {
      if (avail < 8) fail("uncompressed block header truncated");
      const size_t n_raw = load32(p + 4);
      if (n_raw > avail - 8) fail("uncompressed block truncated");
      sink.reserveBlock(out, n_raw);
      std::memcpy(out.data + out.pos, p + 8, n_raw);
      out.pos += n_raw;
      p += 8 + n_raw;
    } else if (magic == kMagicLzvn) {
      if (avail < 12) fail("LZVN block header truncated");
      const size_t n_raw = load32(p + 4), n_payload = load32(p + 8);
      if (n_payload > avail - 12) fail("LZVN block truncated");
      // An LZVN opcode of 2 bytes yields at most 271 bytes: bounds n_raw before allocating.
      if (n_raw > n_payload * 136) fail("LZVN block claims an impossible size");
      sink.reserveBlock(out, n_raw);
      decodeLzvnBlock(p + 12, n_payload, n_raw, out);
      p += 12 + n_payload;
    } else if (magic == kMagicV1 || magic == kMagicV2) {
      const BlockHeader h = magic == kMagicV1 ? parseV1(p, avail) : parseV2(p, avail);
      validate(h);
      const uint64_t block_size =
          uint64_t(h.header_size) + h.n_literal_payload_bytes + h.n_lmd_payload_bytes;
      if (block_size > avail) fail("compressed block truncated");
      sink.reserveBlock(out, h.n_raw_bytes);
      if (literals.size() < h.n_literals + kLiteralSlack)
        literals.resize(h.n_literals + kLiteralSlack);
      decodeLzfseBlock(h, p + h.header_size, end, out, literals.data());
      p += block_size;
    } else {
      fail("unknown block magic 0x" + [&] {
        char buf[16];
        std::snprintf(buf, sizeof buf, "%08x", magic);
        return std::string(buf);
      }() + " at byte " + std::to_string(p - src));
    }
  }
}

}  // namespace
}  // namespace lzfse_detail

std::vector<uint8_t> lzfseDecode(const uint8_t* src, size_t src_size, size_t expected_size_hint,
                                 size_t max_output_bytes) {
  std::vector<uint8_t> bytes;
  if (expected_size_hint)
    bytes.resize(std::min(expected_size_hint, max_output_bytes) + lzfse_detail::kWildCopySlack);
  lzfse_detail::Output out{bytes.data(), 0, bytes.size()};
  lzfse_detail::VectorSink sink(bytes, max_output_bytes);
  lzfse_detail::decodeStream(src, src_size, out, sink);
  bytes.resize(out.pos);
  return bytes;
}

size_t lzfseDecodeInto(const uint8_t* src, size_t src_size, uint8_t* dst, size_t capacity) {
  lzfse_detail::Output out{dst, 0, capacity};
  lzfse_detail::FixedSink sink;
  lzfse_detail::decodeStream(src, src_size, out, sink);
  return out.pos;
}

}  // namespace vf
