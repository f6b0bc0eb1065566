#include "app/memory_check.h"

#include <cstdio>

#include "core/error.h"

namespace vf::app {
namespace {

std::string gib(uint64_t bytes) {
  char text[32];
  std::snprintf(text, sizeof text, "%.1f GiB", double(bytes) / double(uint64_t(1) << 30));
  return text;
}

}  // namespace

std::string outOfMemoryMessage(const std::string& command) {
  if (command == "reconstruct")
    return "out of memory; fusing needs less with larger voxels (raise --voxel-size-m), a shorter range (lower "
           "--max-depth-m) or fewer frames (--max-frames); or free memory, or raise the limit (ulimit -v)";
  return "out of memory (an input states sizes this machine cannot hold)";
}

void checkFitsGpu(uint64_t needed_bytes, const GpuMemory& gpu, const std::string& description) {
  if (needed_bytes <= gpu.free_bytes) return;
  throw Error(description + " needs " + gib(needed_bytes) + " of GPU memory to start, the GPU has " +
              gib(gpu.free_bytes) + " free of " + gib(gpu.total_bytes) +
              "; free the GPU or run on the CPU with --device cpu");
}

}  // namespace vf::app
