#pragma once
// This machine's memory, from /proc/meminfo: what the brick pool may take, and what messages
// about running out of memory quote.
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

}  // namespace vf
