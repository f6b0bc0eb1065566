#pragma once
// LZVN: the byte-oriented LZ77 codec LZFSE uses for small inputs ("bvxn" blocks).
#include <cstddef>
#include <cstdint>

#include "io/lzfse_detail.h"

namespace vf::lzfse_detail {

// Decodes one LZVN payload [src, src + src_size) appending exactly n_raw_bytes to out (the caller
// has checked out.pos + n_raw_bytes <= out.capacity). Throws on any malformed opcode, a distance
// reaching before the stream start, or a size mismatch.
void decodeLzvnBlock(const uint8_t* src, size_t src_size, size_t n_raw_bytes, Output& out);

}  // namespace vf::lzfse_detail
