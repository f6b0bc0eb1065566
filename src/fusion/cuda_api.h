#pragma once
// The few entry points of the CUDA backend (defined in cuda/, compiled by nvcc) that host code
// calls. Only declared here so that src/fusion compiles with a plain C++ compiler; the templates
// are explicitly instantiated in cuda/instantiate.cu for every functor the pipeline runs.
#include <cstddef>
#include <string>

namespace vf::cuda {

int deviceCount();                     // 0 on any driver/runtime error
std::string lastErrorDescription();    // why deviceCount() returned 0
void* allocate(size_t bytes);          // throws vf::Error with the CUDA message
void release(void* ptr) noexcept;
void copyToDevice(void* dst, const void* src, size_t bytes);
void copyToHost(void* dst, const void* src, size_t bytes);
void copyOnDevice(void* dst, const void* src, size_t bytes);
void fillZero(void* dst, size_t bytes);
void synchronize();
// Free and total memory of the current device; false where the query fails (no GPU, no driver).
bool memoryInfo(size_t* free_bytes, size_t* total_bytes) noexcept;

template <class F>
void parallelFor(int n, const F& f);

// Sums the N-float rows produced by f over i in [0, n) into out (double precision on the host).
template <int N, class F>
void parallelReduce(int n, const F& f, double* out);

}  // namespace vf::cuda
