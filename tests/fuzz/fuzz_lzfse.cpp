// Fuzz target: the LZFSE decoder, allocating (capped output) and into a fixed buffer.
#include <vector>

#include "core/error.h"
#include "io/lzfse.h"

extern "C" int LLVMFuzzerTestOneInput(const uint8_t* data, size_t size) {
  constexpr size_t kCap = size_t(64) << 20;  // far above a phone depth map (~200 KB)
  try {
    const std::vector<uint8_t> out = vf::lzfseDecode(data, size, 0, kCap);
    if (out.size() > kCap) std::abort();
  } catch (const vf::Error&) {
  }
  static std::vector<uint8_t> dst(256 * 192 * 4);  // one Record3D depth map
  try {
    const size_t n = vf::lzfseDecodeInto(data, size, dst.data(), dst.size());
    if (n > dst.size()) std::abort();
  } catch (const vf::Error&) {
  }
  return 0;
}
