// The CUDA entry points when vdbfuse is built without CUDA: the CPU path links and runs, and any
// attempt to use the GPU says why it cannot.
#ifndef VDBFUSE_WITH_CUDA
#include "core/error.h"
#include "fusion/cuda_api.h"

namespace vf::cuda {
namespace {
[[noreturn]] void unavailable() {
  throw Error("Device = cuda: this vdbfuse was built without CUDA; Device = cpu runs without it");
}
}  // namespace

int deviceCount() { return 0; }
std::string lastErrorDescription() { return "built without CUDA"; }
void* allocate(size_t) { unavailable(); }
void release(void*) noexcept {}
void copyToDevice(void*, const void*, size_t) { unavailable(); }
void copyToHost(void*, const void*, size_t) { unavailable(); }
void copyOnDevice(void*, const void*, size_t) { unavailable(); }
void fillZero(void*, size_t) { unavailable(); }
void synchronize() {}
bool waitsAfterEachLaunch() { return true; }
void* createEvent() { unavailable(); }
void recordEvent(void*) { unavailable(); }
bool eventReached(void*) { return true; }
float elapsedMs(void*, void*) { unavailable(); }
void destroyEvent(void*) noexcept {}
bool memoryInfo(size_t*, size_t*) noexcept { return false; }

}  // namespace vf::cuda
#endif
