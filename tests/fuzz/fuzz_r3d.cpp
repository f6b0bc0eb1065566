// Fuzz target: a Record3D .r3d capture (zip + metadata JSON + LZFSE depth/confidence + JPEG),
// opened from a temp file, then its first frames loaded.
#include <algorithm>

#include "core/error.h"
#include "fuzz/fuzz_util.h"
#include "io/record3d.h"

extern "C" int LLVMFuzzerTestOneInput(const uint8_t* data, size_t size) {
  const std::string path = vf::fuzz::writeTempInput("_capture.r3d", data, size);
  try {
    vf::Record3dOptions options;
    options.min_confidence = int(size % 3);
    vf::Record3dCapture capture(path, options);
    for (int i = 0; i < std::min(capture.size(), 3); ++i) {
      try {
        const vf::RgbdFrame frame = capture.load(i);
        if (frame.depth.width() != capture.depthIntrinsics().width) std::abort();
      } catch (const vf::Error&) {
      }
    }
  } catch (const vf::Error&) {
  }
  return 0;
}
