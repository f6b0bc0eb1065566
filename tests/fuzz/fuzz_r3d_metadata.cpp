// Fuzz target: the Record3D metadata JSON, and the intrinsics/timestamps derived from it.
#include "core/error.h"
#include "io/record3d.h"

extern "C" int LLVMFuzzerTestOneInput(const uint8_t* data, size_t size) {
  try {
    const vf::Record3dMetadata meta =
        vf::parseRecord3dMetadata(std::string(reinterpret_cast<const char*>(data), size), "fuzz.json");
    if (meta.depth_width > 0 && meta.depth_height > 0)
      vf::scaleRecord3dIntrinsics(meta, meta.depth_width, meta.depth_height);
    for (int i = 0; i < 3; ++i) vf::record3dTimestamp(meta, i);
  } catch (const vf::Error&) {
  }
  return 0;
}
