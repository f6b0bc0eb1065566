#include "app/memory_check.h"

#include <cstdio>
#include <fstream>
#include <sstream>

#include "core/error.h"

namespace vf::app {
namespace {

const char* const kHowToLower =
    "lower --volume-size (memory grows with its cube) or, for the same extent, raise --voxel-size-m and lower "
    "--volume-size together";

std::string gib(uint64_t bytes) {
  char text[32];
  std::snprintf(text, sizeof text, "%.1f GiB", double(bytes) / double(uint64_t(1) << 30));
  return text;
}

}  // namespace

std::optional<HostMemory> readHostMemory() {
  std::ifstream in("/proc/meminfo");
  if (!in) return std::nullopt;
  HostMemory m;
  bool total = false, available = false;
  std::string line;
  while (std::getline(in, line)) {
    std::istringstream fields(line);
    std::string key;
    uint64_t kib = 0;
    if (!(fields >> key >> kib)) continue;
    if (key == "MemTotal:") m.total_bytes = kib * 1024, total = true;
    else if (key == "MemAvailable:") m.available_bytes = kib * 1024, available = true;
    else if (key == "SwapTotal:") m.swap_bytes = kib * 1024;
  }
  if (!total || !available) return std::nullopt;
  return m;
}

std::string checkVolumeFits(uint64_t needed_bytes, const HostMemory& memory, const std::string& volume_description) {
  if (needed_bytes > memory.total_bytes + memory.swap_bytes)
    throw Error("the volume (" + volume_description + ") needs up to " + gib(needed_bytes) +
                " of host memory once every brick is observed, more than this machine's " + gib(memory.total_bytes) +
                " RAM + " + gib(memory.swap_bytes) + " swap; " + kHowToLower);
  if (needed_bytes > memory.available_bytes)
    return "warning: the volume (" + volume_description + ") needs up to " + gib(needed_bytes) +
           " if every brick is observed, more than the " + gib(memory.available_bytes) +
           " available now; a scan that covers the whole volume may run out of memory (" + kHowToLower + ")";
  return {};
}

void checkVolumeFitsGpu(uint64_t needed_bytes, const GpuMemory& gpu, const std::string& volume_description) {
  if (needed_bytes <= gpu.free_bytes) return;
  throw Error("the volume (" + volume_description + ") needs " + gib(needed_bytes) +
              " of GPU memory, the GPU has " + gib(gpu.free_bytes) + " free of " + gib(gpu.total_bytes) + "; " +
              kHowToLower + ", or run on the CPU with --device cpu (its volume costs only the bricks observed)");
}

}  // namespace vf::app
