#include "core/host_memory.h"

#include <sys/mman.h>

#include <fstream>
#include <sstream>
#include <string>

namespace vf {

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

void adviseHugePages(void* p, size_t bytes) {
#ifdef MADV_HUGEPAGE
  madvise(p, bytes, MADV_HUGEPAGE);
#else
  (void)p, (void)bytes;
#endif
}

}  // namespace vf
