#pragma once
// This machine's memory, from /proc/meminfo: what the brick pool may take, and what messages
// about running out of memory quote; and the hint for 2 MiB pages.
#include <cstddef>
#include <cstdint>
#include <optional>

namespace vf {

struct HostMemory {
  uint64_t total_bytes = 0;      // MemTotal
  uint64_t available_bytes = 0;  // MemAvailable
  uint64_t swap_bytes = 0;       // SwapTotal
};

// nullopt where /proc/meminfo cannot be read.
std::optional<HostMemory> readHostMemory();

// Asks for transparent huge pages (2 MiB) over [p, p + bytes), for large arrays that are read
// at random: fewer TLB misses, and one page fault per 2 MiB instead of per 4 KiB. A hint only:
// where the kernel refuses (THP "never", other systems), small pages work as before.
void adviseHugePages(void* p, size_t bytes);

}  // namespace vf
