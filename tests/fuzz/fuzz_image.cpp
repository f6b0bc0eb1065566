// Fuzz target: depth, colour and label PNG decoding (image_io readers on a temp file), and the
// label resampling that follows a label read.
#include "core/error.h"
#include "fuzz/fuzz_util.h"
#include "io/image_io.h"
#include "io/label_maps.h"

extern "C" int LLVMFuzzerTestOneInput(const uint8_t* data, size_t size) {
  const std::string path = vf::fuzz::writeTempInput("_image.png", data, size);
  try {
    const vf::DepthImage depth = vf::readDepthPng(path);
    if (depth.width() <= 0 || depth.height() <= 0) std::abort();
  } catch (const vf::Error&) {
  }
  try {
    vf::readColorImage(path);
  } catch (const vf::Error&) {
  }
  try {
    const vf::LabelImage labels = vf::readLabelPng(path);
    vf::resampleLabelsNearest(labels, 13, 7);
  } catch (const vf::Error&) {
  }
  return 0;
}
