#pragma once
// PNG/JPG images in and out of the core image types. Depth PNGs are 16-bit (TUM: value / 5000 =
// metres, 0 = no reading); label maps are single-channel 8- or 16-bit class ids. Writers never
// leave a half-written file behind (core/atomic_output.h). The readers refuse, naming the file,
// a truncated or corrupt file and an image of more than 100 Mpx (io/image_codec.h) before they
// allocate it.
#include <string>

#include "core/image.h"

namespace vf {

// TUM, ETH3D and most RGB-D datasets: 5000 PNG units per metre (0.2 mm steps).
constexpr float kTumDepthUnitsPerMetre = 5000.f;

// 16-bit single-channel PNG -> metres (value / units_per_metre, 0 stays 0 = invalid).
// Throws vf::Error naming the file when it is missing, unreadable, or not 16-bit single-channel.
DepthImage readDepthPng(const std::string& path, float units_per_metre = kTumDepthUnitsPerMetre);

// Colour PNG/JPG (grey, RGB or RGBA, 8 or 16 bit) -> Rgb8 with a = 255. Pixels as stored (no EXIF
// rotation), so label maps made from the same files stay aligned.
ColorImage readColorImage(const std::string& path);

// Single-channel 8- or 16-bit PNG of class ids. A colour (3/4-channel) map is an error, since
// its pixel values are not class ids.
LabelImage readLabelPng(const std::string& path);

// Metres -> 16-bit PNG (rounded, clamped to 65535; non-finite or <= 0 become 0).
void writeDepthPng(const std::string& path, const DepthImage& depth_m,
                   float units_per_metre = kTumDepthUnitsPerMetre);
// Colour -> 8-bit RGB PNG (alpha dropped).
void writeColorPng(const std::string& path, const ColorImage& color);
// Class ids -> 8-bit PNG when every id fits in a byte, else 16-bit.
void writeLabelPng(const std::string& path, const LabelImage& labels);

}  // namespace vf
