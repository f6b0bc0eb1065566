#include "fusion/device.h"

#include "core/error.h"
#include "fusion/cuda_api.h"

namespace vf {

Device parseDevice(const std::string& name) {
  if (name == "cpu") return Device::Cpu;
  if (name == "cuda") return Device::Cuda;
  if (name == "auto") return Device::Auto;
  throw Error("Device = '" + name + "': expected cpu, cuda or auto");
}

std::string deviceName(Device device) {
  switch (device) {
    case Device::Cpu: return "cpu";
    case Device::Cuda: return "cuda";
    default: return "auto";
  }
}

bool cudaBuilt() {
#ifdef VDBFUSE_WITH_CUDA
  return true;
#else
  return false;
#endif
}

int cudaDeviceCount() {
#ifdef VDBFUSE_WITH_CUDA
  return cuda::deviceCount();
#else
  return 0;
#endif
}

bool cudaMemoryInfo(uint64_t& free_bytes, uint64_t& total_bytes) {
  size_t free_now = 0, total = 0;
  if (!cuda::memoryInfo(&free_now, &total)) return false;
  free_bytes = free_now;
  total_bytes = total;
  return true;
}

Device resolveDevice(Device requested) {
  if (requested == Device::Cpu) return Device::Cpu;
  const int gpus = cudaDeviceCount();
  if (requested == Device::Auto) return gpus > 0 ? Device::Cuda : Device::Cpu;
  if (!cudaBuilt())
    throw Error("Device = cuda: this vdbfuse was built without CUDA (configure with nvcc available "
                "and -DVDBFUSE_WITH_CUDA=ON); Device = cpu runs without it");
  if (gpus == 0)
    throw Error("Device = cuda: no usable CUDA GPU found (" + cuda::lastErrorDescription() +
                "); Device = cpu runs without one");
  return Device::Cuda;
}

}  // namespace vf
