#pragma once
// Procedural colour for every surface of the room. The tracker has a photometric term, and a
// plain wall would let it slide, so each material carries texture at a few centimetres to tens
// of centimetres (coarser than a pixel at 4 m, 7.6 mm, so it does not alias into noise).
#include "room_geometry.h"

namespace vf::synth {

// sRGB colour, 0..255 per channel, of primitive `p` at the surface point `x` with outward normal `n`.
Vec3 surfaceColor(const Primitive& p, const Vec3& x, const Vec3& n);

}  // namespace vf::synth
