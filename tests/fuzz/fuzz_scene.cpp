// Fuzz target: .vdb scene documents (readScene on a temp file), then the queries the commands
// run on a scene that loaded.
#include "core/error.h"
#include "fuzz/fuzz_util.h"
#include "vdb/scene.h"

extern "C" int LLVMFuzzerTestOneInput(const uint8_t* data, size_t size) {
  const std::string path = vf::fuzz::writeTempInput("_scene.vdb", data, size);
  try {
    const vf::Scene scene = vf::readScene(path);
    scene.activeVoxelCount();
    scene.hasClasses();
  } catch (const vf::Error&) {
  }
  return 0;
}
