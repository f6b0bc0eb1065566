#pragma once
// Hand-made PNGs for the codec tests: any IHDR, optional PLTE / tRNS, and rows filtered with the
// filter type the caller picks per row (the encoders under test only ever pick their own).
#include <zlib.h>

#include <algorithm>
#include <cstdint>
#include <cstdlib>
#include <functional>
#include <string>
#include <vector>

namespace vf::test {

inline void appendBe32(std::string& s, uint32_t v) {
  for (int shift = 24; shift >= 0; shift -= 8) s += char((v >> shift) & 0xFF);
}

inline void appendChunk(std::string& png, const std::string& type, const std::string& data) {
  appendBe32(png, uint32_t(data.size()));
  const std::string body = type + data;
  png += body;
  appendBe32(png, uint32_t(crc32(0, reinterpret_cast<const Bytef*>(body.data()), uInt(body.size()))));
}

// Row `row` (unfiltered bytes) filtered with PNG filter `type` (0-4) against `prev` (the row
// above, unfiltered; empty above the first), `bpp` bytes a pixel (at least 1).
inline std::string filterRow(int type, const std::string& row, const std::string& prev, int bpp) {
  auto at = [](const std::string& s, long i) { return i >= 0 && size_t(i) < s.size() ? int(uint8_t(s[size_t(i)])) : 0; };
  std::string out(1, char(type));
  for (long i = 0; i < long(row.size()); ++i) {
    const int a = at(row, i - bpp), b = at(prev, i), c = at(prev, i - bpp);
    int predictor = 0;
    if (type == 1) predictor = a;
    if (type == 2) predictor = b;
    if (type == 3) predictor = (a + b) / 2;
    if (type == 4) {
      const int p = a + b - c, pa = std::abs(p - a), pb = std::abs(p - b), pc = std::abs(p - c);
      predictor = pa <= pb && pa <= pc ? a : (pb <= pc ? b : c);
    }
    out += char(uint8_t(at(row, i) - predictor));
  }
  return out;
}

// A PNG of IHDR fields, optional PLTE / tRNS bodies, and `raw`: every row's filter byte and
// bytes, deflated as they are (a test can write any filter byte).
inline std::string makePngOfRawRows(uint32_t width, uint32_t height, int bit_depth, int color_type,
                                    const std::string& raw, const std::string& plte = "",
                                    const std::string& trns = "") {
  std::string ihdr;
  appendBe32(ihdr, width);
  appendBe32(ihdr, height);
  ihdr += char(bit_depth);
  ihdr += char(color_type);
  ihdr += std::string(3, '\0');  // deflate, adaptive filters, no interlace
  std::string png = "\x89PNG\r\n\x1a\n";
  appendChunk(png, "IHDR", ihdr);
  if (!plte.empty()) appendChunk(png, "PLTE", plte);
  if (!trns.empty()) appendChunk(png, "tRNS", trns);
  std::vector<Bytef> packed(compressBound(uLong(raw.size())) + 16);
  uLongf packed_size = uLongf(packed.size());
  compress(packed.data(), &packed_size, reinterpret_cast<const Bytef*>(raw.data()), uLong(raw.size()));
  appendChunk(png, "IDAT", std::string(reinterpret_cast<const char*>(packed.data()), packed_size));
  appendChunk(png, "IEND", "");
  return png;
}

// A PNG from its parts: IHDR fields, optional PLTE / tRNS bodies, and the unfiltered rows
// (`rows` without filter bytes), row y filtered with filter_of_row(y) (default: none).
inline std::string makePng(uint32_t width, uint32_t height, int bit_depth, int color_type, const std::string& rows,
                           const std::string& plte = "", const std::string& trns = "",
                           const std::function<int(int)>& filter_of_row = nullptr) {
  const int channels = color_type == 2 ? 3 : color_type == 6 ? 4 : color_type == 4 ? 2 : 1;
  const int bpp = std::max(1, channels * bit_depth / 8);
  std::string raw;
  const size_t row_bytes = height ? rows.size() / height : 0;
  for (uint32_t y = 0; y < height; ++y) {
    const std::string prev = y > 0 ? rows.substr((y - 1) * row_bytes, row_bytes) : std::string();
    raw += filterRow(filter_of_row ? filter_of_row(int(y)) : 0, rows.substr(y * row_bytes, row_bytes), prev, bpp);
  }
  return makePngOfRawRows(width, height, bit_depth, color_type, raw, plte, trns);
}

}  // namespace vf::test
