#pragma once
// Does a volume fit in this machine's memory? Checked before the volume is reserved, so a run
// that cannot finish says so at once instead of being killed by the OOM killer hours later.
#include <cstdint>
#include <optional>
#include <string>

namespace vf::app {

struct HostMemory {
  uint64_t total_bytes = 0;      // MemTotal
  uint64_t available_bytes = 0;  // MemAvailable
  uint64_t swap_bytes = 0;       // SwapTotal
};

// From /proc/meminfo; nullopt where it cannot be read (then nothing is checked).
std::optional<HostMemory> readHostMemory();

// `needed_bytes` is the worst case (every brick of the volume touched). Throws vf::Error when it
// exceeds RAM + swap, naming the size and the options that lower it; returns a warning line when
// it exceeds the memory available now; else an empty string.
std::string checkVolumeFits(uint64_t needed_bytes, const HostMemory& memory, const std::string& volume_description);

struct GpuMemory {
  uint64_t free_bytes = 0;
  uint64_t total_bytes = 0;
};

// The CUDA backend allocates the whole dense volume (and the frame buffers) when it starts, so
// `needed_bytes` must fit in what the GPU has free now: throws vf::Error naming both sizes and the
// options that lower the need.
void checkVolumeFitsGpu(uint64_t needed_bytes, const GpuMemory& gpu, const std::string& volume_description);

}  // namespace vf::app
