#pragma once
// The PNGs of RGB-D frames (8- or 16-bit grey, 8-bit RGB or RGBA, not interlaced) decoded on
// libdeflate, whose inflate is about twice zlib's; image_codec.cpp hands every other PNG, and
// every file this path does not finish, to libpng, which decodes it or words its error. So this
// path never throws and never changes what a file decodes to: only how fast.
//
// It checks what libpng checks for such a file: the signature, IHDR first, the CRC of every
// critical chunk, consecutive IDAT chunks, the zlib stream's checksum, exactly the rows' bytes
// inflated, a known filter type per row, and an IEND after the pixels (a file cut after them is
// refused, as libpng and OpenCV refuse it).
#include <cstddef>
#include <cstdint>

namespace vf::png_inflate {

enum class Layout { Grey8, Grey16, Rgb8, Rgba8 };

// Unfiltered rows as stored (16-bit samples big-endian): row y starts at data + y * stride and
// holds row_bytes bytes. They live in a buffer of the calling thread, valid until its next call.
struct Rows {
  int width = 0, height = 0;
  size_t row_bytes = 0, stride = 0;
  const uint8_t* data = nullptr;
  const uint8_t* row(int y) const { return data + size_t(y) * stride; }
};

// True, with `rows`, when the file is a PNG of exactly `layout` (and at most max_pixels pixels)
// that this path decoded; false for anything else.
bool decode(const uint8_t* file, size_t size, Layout layout, uint64_t max_pixels, Rows& rows);

}  // namespace vf::png_inflate
