#pragma once
// Does a run fit in this machine's memory? The sparse volume grows with the scene and stops the
// run cleanly when memory runs out; what is checked up front is what the backend allocates when it
// starts, so that a GPU run that cannot even begin says so at once.
#include <cstdint>
#include <string>

namespace vf::app {

struct GpuMemory {
  uint64_t free_bytes = 0;
  uint64_t total_bytes = 0;
};

// The CUDA backend allocates its frame buffers and the first part of the brick pool when it
// starts, so `needed_bytes` must fit in what the GPU has free now: throws vf::Error naming both
// sizes and what to do instead.
void checkFitsGpu(uint64_t needed_bytes, const GpuMemory& gpu, const std::string& description);

// What a command that ran out of host memory (std::bad_alloc) tells the user: for reconstruct,
// the options that lower what it needs; for the others, that an input asks for more than the
// machine holds. `command` is the command's name ("" when none was parsed).
std::string outOfMemoryMessage(const std::string& command);

}  // namespace vf::app
