#pragma once
// The CUDA side of fusion/parallel.h: runs a fusion functor over [0, n) on the GPU.
//
// parallelFor: one thread per element over a grid-stride loop, 256 threads per block.
// parallelReduce: each thread sums its rows in float registers, a warp-shuffle + shared-memory
// tree reduces each block to one partial row in a preallocated scratch buffer, a second tiny
// kernel sums the partials per component in double in a fixed order, and only those N doubles
// cross the bus. Deterministic for a given n (no atomics in the reduction).
//
// Both are synchronous for now: the pipeline times stages on the host (ScopedStage), which is
// only honest if a stage's kernels have finished when it returns. A stream-ordered version would
// take a cudaStream_t (one per Pipeline), drop the cudaDeviceSynchronize here, and time stages
// with cudaEventRecord/cudaEventElapsedTime on that stream instead of the host clock.
#include <cuda_runtime.h>

#include <string>

#include "check.h"
#include "fusion/cuda_api.h"

namespace vf::cuda {

constexpr int kBlockThreads = 256;
constexpr int kMaxForBlocks = 1 << 20;   // keeps i + stride below 2^32 (unsigned loop counter)
constexpr int kMaxReduceBlocks = 1024;   // partial rows per reduction (1024 x N floats scratch)

template <class F>
__global__ void __launch_bounds__(kBlockThreads) forEachKernel(int n, F f) {
  const unsigned stride = gridDim.x * blockDim.x;
  for (unsigned i = blockIdx.x * blockDim.x + threadIdx.x; i < unsigned(n); i += stride) f(int(i));
}

// One partial row per block: partials[blockIdx.x * N + k].
template <int N, class F>
__global__ void __launch_bounds__(kBlockThreads) reduceRowsKernel(int n, F f, float* partials) {
  float acc[N];
#pragma unroll
  for (int k = 0; k < N; ++k) acc[k] = 0.f;
  float row[N];
  const unsigned stride = gridDim.x * blockDim.x;
  for (unsigned i = blockIdx.x * blockDim.x + threadIdx.x; i < unsigned(n); i += stride) {
    if (!f(int(i), row)) continue;
#pragma unroll
    for (int k = 0; k < N; ++k) acc[k] += row[k];
  }
  constexpr int kWarps = kBlockThreads / 32;
  __shared__ float warp_sums[kWarps][N];
  const int lane = threadIdx.x & 31, warp = threadIdx.x >> 5;
#pragma unroll
  for (int k = 0; k < N; ++k) {
    float v = acc[k];
#pragma unroll
    for (int offset = 16; offset > 0; offset >>= 1) v += __shfl_down_sync(0xffffffffu, v, offset);
    if (lane == 0) warp_sums[warp][k] = v;
  }
  __syncthreads();
  for (int k = threadIdx.x; k < N; k += blockDim.x) {
    float s = 0.f;
#pragma unroll
    for (int w = 0; w < kWarps; ++w) s += warp_sums[w][k];
    partials[size_t(blockIdx.x) * N + k] = s;
  }
}

template <class F>
void parallelFor(int n, const F& f) {
  if (n <= 0) return;
  const int blocks = (n + kBlockThreads - 1) / kBlockThreads;
  forEachKernel<F><<<blocks < kMaxForBlocks ? blocks : kMaxForBlocks, kBlockThreads>>>(n, f);
  detail::check(cudaGetLastError(), std::string("launch of ") + __PRETTY_FUNCTION__);
  // Synchronous so that host-side stage timings are true and errors name the kernel.
  detail::check(cudaDeviceSynchronize(), std::string("kernel ") + __PRETTY_FUNCTION__);
}

template <int N, class F>
void parallelReduce(int n, const F& f, double* out) {
  for (int k = 0; k < N; ++k) out[k] = 0.0;
  if (n <= 0) return;
  int blocks = (n + kBlockThreads - 1) / kBlockThreads;
  if (blocks > kMaxReduceBlocks) blocks = kMaxReduceBlocks;
  detail::ReduceScratch scratch(size_t(kMaxReduceBlocks) * N, size_t(N));
  reduceRowsKernel<N, F><<<blocks, kBlockThreads>>>(n, f, scratch.partials());
  detail::check(cudaGetLastError(), std::string("launch of ") + __PRETTY_FUNCTION__);
  scratch.sumToHost(blocks, N, out, __PRETTY_FUNCTION__);
}

}  // namespace vf::cuda
