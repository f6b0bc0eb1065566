#pragma once
#include <cstdint>
#include <string>

namespace vf {

// Which backend runs the fusion stages. Auto resolves to Cuda when a GPU is usable.
enum class Device { Cpu, Cuda, Auto };

Device parseDevice(const std::string& name);  // "cpu" | "cuda" | "auto", else vf::Error
std::string deviceName(Device device);
bool cudaBuilt();                  // compiled with the CUDA backend
int cudaDeviceCount();             // 0 when not built or no GPU / no driver
Device resolveDevice(Device requested);  // throws a clear vf::Error when CUDA is asked for but unusable
// Free and total memory of the CUDA device; false when not built, without a GPU, or on error.
bool cudaMemoryInfo(uint64_t& free_bytes, uint64_t& total_bytes);

}  // namespace vf
