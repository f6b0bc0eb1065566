#pragma once
// Turning CUDA status codes into vf::Error (DESIGN.md: CUDA errors throw, never exit()).
// Internal to cuda/: compiled by nvcc only.
#include <cuda_runtime_api.h>

#include <cstddef>
#include <mutex>
#include <string>

namespace vf::cuda::detail {

// Throws vf::Error "CUDA <call> failed: <name> (<description>)" unless status is cudaSuccess.
// Non-sticky errors are cleared first, so the next call does not report this one again.
void check(cudaError_t status, const std::string& call);
// The same, the call named `prefix` + `what`, a string built only on failure: for launches and
// waits on the hot path, where building it every time cost as much as the launch.
inline void check(cudaError_t status, const char* prefix, const char* what) {
  if (status != cudaSuccess) check(status, std::string(prefix) + what);
}

// Device scratch for parallelReduce: partial rows per block and the final sums, allocated on
// first use and kept for the life of the process (no cudaMalloc per reduction). An instance is
// a lease that holds a lock, so concurrent host threads take turns (the GPU serialises the
// kernels anyway).
class ReduceScratch {
 public:
  ReduceScratch(size_t partial_floats, size_t sum_doubles);
  ReduceScratch(const ReduceScratch&) = delete;
  ReduceScratch& operator=(const ReduceScratch&) = delete;
  float* partials() const { return partials_; }
  double* sums() const { return sums_; }

  // Sums component k of `blocks` partial rows of n_components floats (in double, fixed order,
  // on the GPU) and copies the n_components doubles to out; waits for and checks all kernels
  // queued before it. `what` names the reduction in error messages (made into a string only then).
  void sumToHost(int blocks, int n_components, double* out, const char* what) const;
  // The same for two reductions whose partial rows lie one after the other (first_blocks rows,
  // then second_blocks rows): one copy, one wait.
  void sumTwoToHost(int first_blocks, int second_blocks, int n_components, double* out_first, double* out_second,
                    const char* what) const;

 private:
  std::unique_lock<std::mutex> lock_;
  float* partials_ = nullptr;
  double* sums_ = nullptr;
};

}  // namespace vf::cuda::detail
