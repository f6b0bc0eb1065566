// Fuzz target: TUM file lists (rgb.txt, depth.txt) and camera_intrinsics.txt, read from a file.
#include "core/error.h"
#include "fuzz/fuzz_util.h"
#include "io/tum_dataset.h"

extern "C" int LLVMFuzzerTestOneInput(const uint8_t* data, size_t size) {
  const std::string path = vf::fuzz::writeTempInput("_list.txt", data, size);
  try {
    const std::vector<vf::TimedFile> files = vf::readTumFileList(path);
    if (files.empty()) std::abort();  // documented: an empty list is an error, never a result
  } catch (const vf::Error&) {
  }
  try {
    vf::readCameraIntrinsicsFile(path);
  } catch (const vf::Error&) {
  }
  try {
    vf::parsePinholeOverride(std::string(reinterpret_cast<const char*>(data), size));
  } catch (const vf::Error&) {
  }
  return 0;
}
