#pragma once
#include <string>

namespace vf {

// Which backend runs the fusion stages. Auto resolves to Cuda when a GPU is usable.
enum class Device { Cpu, Cuda, Auto };

Device parseDevice(const std::string& name);  // "cpu" | "cuda" | "auto", else vf::Error
std::string deviceName(Device device);
bool cudaBuilt();                  // compiled with the CUDA backend
int cudaDeviceCount();             // 0 when not built or no GPU / no driver
Device resolveDevice(Device requested);  // throws a clear vf::Error when CUDA is asked for but unusable

}  // namespace vf
