#pragma once
// PNG and JPEG decoding and PNG encoding with libpng (the common PNGs inflated by libdeflate,
// io/png_inflate.h), libjpeg-turbo and zlib alone: what the frame
// readers need, without OpenCV and its dependency tree, so that the GPU bundle can carry them
// (cuda/README.md). Decoded pixels are those cv::imread(IMREAD_UNCHANGED) gives, followed by the
// conversions image_io.h's readers have always made (tests/io/image_codec_test.cpp compares the
// two on real frames).
//
// Every decoder reads the header first and refuses, with a vf::Error naming `name`, an image with
// a zero side or more than kMaxImagePixels before it allocates anything; a truncated or corrupt
// file is an error too, never an image with a grey or missing end.
#include <cstddef>
#include <cstdint>
#include <string>
#include <vector>

#include "core/image.h"

namespace vf {

// 100 Mpx: ten times the largest RGB-D frame seen (Replica 1200x680 is 0.8 Mpx).
constexpr uint64_t kMaxImagePixels = 100'000'000;

// An image as stored: 1 (grey), 3 (colour) or 4 (colour with alpha) channels of 8 or 16 bits,
// as OpenCV's IMREAD_UNCHANGED counts them (a palette PNG is colour; grey + alpha counts 4).
struct ImageHeader {
  int width = 0, height = 0;
  int channels = 0;
  int bits = 0;
  std::string describe() const;  // "16-bit 1-channel"
};

// The whole file; throws vf::Error "<what> not found: <path>" or naming the read failure.
std::vector<uint8_t> readFileBytes(const std::string& path, const std::string& what);

// PNG or JPEG (told by its signature), header only.
ImageHeader decodeImageHeader(const uint8_t* data, size_t size, const std::string& name);

// OpenEXR header only: the data window's size (channels and bits left 0), checked like the
// others before a caller hands the file to a decoder that allocates whatever it states (OpenCV).
ImageHeader decodeExrHeader(const uint8_t* data, size_t size, const std::string& name, const std::string& what);

// 16-bit single-channel PNG -> metres (value / units_per_metre; 0 stays 0). Any other PNG is an
// error naming its type; `what` ("depth image") starts the messages.
DepthImage decodeDepthPng(const uint8_t* data, size_t size, const std::string& name, float units_per_metre,
                          const std::string& what = "depth image");

// PNG or JPEG, grey / RGB / RGBA (alpha dropped), 8 or 16 bit (rounded to 8) -> Rgb8, a = 255.
// Pixels as stored: no EXIF rotation.
ColorImage decodeColorImage(const uint8_t* data, size_t size, const std::string& name,
                            const std::string& what = "colour image");

// Single-channel 8- or 16-bit PNG, values as stored. `header` receives what the file holds, so
// that the caller can word its own error for any other kind (a colour-coded label map).
// Returns an empty image when the file is not single-channel.
Image<uint16_t> decodeGreyPng(const uint8_t* data, size_t size, const std::string& name, ImageHeader& header,
                              const std::string& what);

// How hard PNG writing compresses. Fast: OpenCV's defaults (zlib level 1, run-length strategy,
// the Sub filter). Compact: zlib's default level 6 and libpng's adaptive filter choice per row,
// for files written once and carried often (the GPU bundle's frames). On TUM fr1_xyz depth:
// Fast 84 % of TUM's own PNG size at 10 ms a frame, Compact 71 % at 46 ms; level 9 would give
// 67 % at 580 ms.
enum class PngCompression { Fast, Compact };

// PNG bytes of row-major pixels: channels 1 (grey) or 3 (RGB), bits 8 or 16 (native-endian
// uint16_t samples). `name` names the target in errors.
std::string encodePng(const void* pixels, int width, int height, int channels, int bits, const std::string& name,
                      PngCompression compression = PngCompression::Fast);

// Baseline JPEG bytes (4:2:0, optimised Huffman tables) of an RGBA image; alpha is ignored.
std::string encodeJpeg(const ColorImage& color, int quality, const std::string& name);

}  // namespace vf
