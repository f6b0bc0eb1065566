#include "io/png_inflate.h"

#include <libdeflate.h>

#include <cstdlib>
#include <cstring>
#include <memory>
#include <vector>

namespace vf::png_inflate {
namespace {

constexpr uint8_t kSignature[8] = {0x89, 'P', 'N', 'G', '\r', '\n', 0x1a, '\n'};
constexpr uint32_t kMaxSide = 1u << 20;  // libpng's user limit in image_codec.cpp

uint32_t bigEndian32(const uint8_t* p) {
  return uint32_t(p[0]) << 24 | uint32_t(p[1]) << 16 | uint32_t(p[2]) << 8 | uint32_t(p[3]);
}

bool isLetter(uint8_t c) { return (c >= 'A' && c <= 'Z') || (c >= 'a' && c <= 'z'); }

struct Chunk {
  const uint8_t* type = nullptr;  // 4 bytes, then the body, then the CRC
  const uint8_t* body = nullptr;
  uint32_t length = 0;
  bool is(const char* name) const { return std::memcmp(type, name, 4) == 0; }
  bool critical() const { return (type[0] & 0x20) == 0; }
  bool crcMatches() const {
    return uint32_t(libdeflate_crc32(0, type, size_t(length) + 4)) == bigEndian32(body + length);
  }
};

// The chunk at *pos, or false where the file ends inside it or its name is not four letters.
bool nextChunk(const uint8_t* file, size_t size, size_t* pos, Chunk* chunk) {
  if (size - *pos < 12) return false;
  const uint32_t length = bigEndian32(file + *pos);
  if (length > 0x7fffffffu || length > size - *pos - 12) return false;
  chunk->length = length;
  chunk->type = file + *pos + 4;
  chunk->body = chunk->type + 4;
  for (int k = 0; k < 4; ++k)
    if (!isLetter(chunk->type[k])) return false;
  *pos += size_t(length) + 12;
  return true;
}

struct LayoutFields {
  int bit_depth, color_type, channels;
};

LayoutFields fieldsOf(Layout layout) {
  switch (layout) {
    case Layout::Grey8: return {8, 0, 1};
    case Layout::Grey16: return {16, 0, 1};
    case Layout::Rgb8: return {8, 2, 3};
    case Layout::Rgba8: return {8, 6, 4};
  }
  return {0, 0, 0};
}

int paeth(int a, int b, int c) {
  const int p = a + b - c;
  const int pa = std::abs(p - a), pb = std::abs(p - b), pc = std::abs(p - c);
  return pa <= pb && pa <= pc ? a : (pb <= pc ? b : c);
}

// Undoes one row's filter in place; `prev` is the row above, unfiltered (zeros above the first).
// The left neighbours are carried in locals: reading back what the previous iteration just
// stored, Bpp bytes away, would wait on store forwarding at every byte.
template <int Bpp>
bool unfilterRow(uint8_t filter, uint8_t* row, const uint8_t* prev, size_t n) {
  switch (filter) {
    case 0: return true;
    case 1: {
      uint8_t left[Bpp] = {};
      for (size_t i = 0; i < n; i += Bpp)
#pragma GCC unroll 4
        for (int k = 0; k < Bpp; ++k) row[i + k] = left[k] = uint8_t(row[i + k] + left[k]);
      return true;
    }
    case 2:
      for (size_t i = 0; i < n; ++i) row[i] = uint8_t(row[i] + prev[i]);
      return true;
    case 3: {
      uint8_t left[Bpp] = {};
      for (size_t i = 0; i < n; i += Bpp)
#pragma GCC unroll 4
        for (int k = 0; k < Bpp; ++k)
          row[i + k] = left[k] = uint8_t(row[i + k] + ((int(left[k]) + int(prev[i + k])) >> 1));
      return true;
    }
    case 4: {
      uint8_t left[Bpp] = {}, up_left[Bpp] = {};
      for (size_t i = 0; i < n; i += Bpp)
#pragma GCC unroll 4
        for (int k = 0; k < Bpp; ++k) {
          const uint8_t up = prev[i + k];
          row[i + k] = left[k] = uint8_t(row[i + k] + paeth(left[k], up, up_left[k]));
          up_left[k] = up;
        }
      return true;
    }
    default: return false;  // libpng: "bad adaptive filter value"
  }
}

template <int Bpp>
bool unfilterRows(uint8_t* zero_row_then_rows, size_t stride, int height) {
  for (int y = 0; y < height; ++y) {
    uint8_t* line = zero_row_then_rows + size_t(y + 1) * stride;  // filter byte, then the row
    const uint8_t* prev = zero_row_then_rows + size_t(y) * stride + 1;
    if (!unfilterRow<Bpp>(line[0], line + 1, prev, stride - 1)) return false;
  }
  return true;
}

// Per thread, reused from frame to frame: a fresh megabyte per decode would be paged in anew.
struct Scratch {
  std::vector<uint8_t> compressed;  // the IDAT bodies, joined when there are several
  std::vector<uint8_t> pixels;      // a zero row, then each row's filter byte and bytes
  std::unique_ptr<libdeflate_decompressor, void (*)(libdeflate_decompressor*)> inflater{
      libdeflate_alloc_decompressor(), libdeflate_free_decompressor};
};

}  // namespace

bool decode(const uint8_t* file, size_t size, Layout layout, uint64_t max_pixels, Rows& rows) {
  if (size < 8 || std::memcmp(file, kSignature, 8) != 0) return false;
  size_t pos = 8;
  Chunk chunk;
  if (!nextChunk(file, size, &pos, &chunk) || !chunk.is("IHDR") || chunk.length != 13 || !chunk.crcMatches())
    return false;
  const uint32_t width = bigEndian32(chunk.body), height = bigEndian32(chunk.body + 4);
  const LayoutFields want = fieldsOf(layout);
  const uint8_t* f = chunk.body + 8;  // bit depth, colour type, compression, filter, interlace
  if (f[0] != want.bit_depth || f[1] != want.color_type || f[2] != 0 || f[3] != 0 || f[4] != 0) return false;
  if (width == 0 || height == 0 || width > kMaxSide || height > kMaxSide || uint64_t(width) * height > max_pixels)
    return false;

  thread_local Scratch scratch;
  if (!scratch.inflater) return false;
  const uint8_t* idat = nullptr;  // the first IDAT body, used in place when it is the only one
  size_t idat_chunks = 0, idat_bytes = 0;
  bool idat_ended = false, found_end = false;
  scratch.compressed.clear();
  while (!found_end) {
    if (!nextChunk(file, size, &pos, &chunk)) return false;  // truncated: libpng words it
    if (chunk.is("IDAT")) {
      if (idat_ended || !chunk.crcMatches()) return false;
      if (idat_chunks == 1) scratch.compressed.assign(idat, idat + idat_bytes);
      if (idat_chunks >= 1) scratch.compressed.insert(scratch.compressed.end(), chunk.body, chunk.body + chunk.length);
      if (idat_chunks == 0) idat = chunk.body;
      idat_bytes += chunk.length;
      ++idat_chunks;
      continue;
    }
    idat_ended = idat_chunks > 0;
    if (chunk.is("IEND")) {
      found_end = chunk.crcMatches();
      if (!found_end) return false;
    } else if (chunk.critical() || chunk.is("tRNS")) {
      return false;  // a palette, an unknown critical chunk, or transparency that adds a channel
    }
  }
  if (idat_chunks == 0) return false;
  if (idat_chunks > 1) idat = scratch.compressed.data();

  const size_t row_bytes = size_t(width) * size_t(want.channels) * size_t(want.bit_depth / 8);
  const size_t stride = row_bytes + 1;
  scratch.pixels.resize(stride * (size_t(height) + 1));
  uint8_t* pixels = scratch.pixels.data();
  std::memset(pixels, 0, stride);
  if (libdeflate_zlib_decompress(scratch.inflater.get(), idat, idat_bytes, pixels + stride, stride * height,
                                 nullptr) != LIBDEFLATE_SUCCESS)
    return false;
  bool unfiltered = false;
  switch (want.channels * want.bit_depth / 8) {  // bytes per pixel
    case 1: unfiltered = unfilterRows<1>(pixels, stride, int(height)); break;
    case 2: unfiltered = unfilterRows<2>(pixels, stride, int(height)); break;
    case 3: unfiltered = unfilterRows<3>(pixels, stride, int(height)); break;
    case 4: unfiltered = unfilterRows<4>(pixels, stride, int(height)); break;
  }
  if (!unfiltered) return false;
  rows.width = int(width);
  rows.height = int(height);
  rows.row_bytes = row_bytes;
  rows.stride = stride;
  rows.data = pixels + stride + 1;
  return true;
}

}  // namespace vf::png_inflate
