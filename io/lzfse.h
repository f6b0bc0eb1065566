#pragma once
// LZFSE decompression (Apple's LZ77 + finite-state-entropy codec), written from the public format
// description. Record3D stores each iPhone depth and confidence map as one LZFSE stream.
//
// A stream is a sequence of blocks, each opened by a 4-byte magic:
//   "bvx$" end of stream, "bvx-" uncompressed, "bvx1" LZFSE with a plain header,
//   "bvx2" LZFSE with a bit-packed header, "bvxn" LZVN.
// Every read and write is bounds-checked: a truncated or corrupted stream throws vf::Error whose
// message starts with "LZFSE:"; it never reads or writes outside the buffers it was given.
#include <cstddef>
#include <cstdint>
#include <vector>

namespace vf {

// Default ceiling on the decoded size: a hostile header cannot make the decoder allocate more.
constexpr size_t kLzfseMaxOutputBytes = size_t(1) << 30;

// Decodes a whole stream. expected_size_hint (0 = unknown) only pre-sizes the output buffer;
// max_output_bytes caps the decoded size (exceeding it is an error, not a truncation).
std::vector<uint8_t> lzfseDecode(const uint8_t* src, size_t src_size, size_t expected_size_hint = 0,
                                 size_t max_output_bytes = kLzfseMaxOutputBytes);

inline std::vector<uint8_t> lzfseDecode(const std::vector<uint8_t>& src,
                                        size_t expected_size_hint = 0,
                                        size_t max_output_bytes = kLzfseMaxOutputBytes) {
  return lzfseDecode(src.data(), src.size(), expected_size_hint, max_output_bytes);
}

// Decodes a whole stream into dst (capacity bytes) without allocating the output; returns the
// decoded size. A stream that decodes to more than capacity bytes throws. Bytes of dst past the
// returned size may have been overwritten (the decoder copies in 16-byte steps where it can).
size_t lzfseDecodeInto(const uint8_t* src, size_t src_size, uint8_t* dst, size_t capacity);

}  // namespace vf
