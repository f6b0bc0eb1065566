#pragma once
// The CUDA side of fusion/parallel.h: runs a fusion functor over [0, n) on the GPU.
//
// parallelFor: one thread per element over a grid-stride loop, 256 threads per block.
// parallelReduce: each thread sums its rows in float registers, a warp-shuffle + shared-memory
// tree reduces each block to one partial row in a preallocated scratch buffer, a second tiny
// kernel sums the partials per component in double in a fixed order, and only those N doubles
// cross the bus. Deterministic for a given n (no atomics in the reduction).
//
// Stream-ordered: a launch is queued on the default stream and parallelFor returns at once; the
// host waits only where it reads a result (parallelReduce's sums, copyToHost). Stages are timed
// by events on the same stream (fusion/stage_timer.h), so a stage's time is its work on the GPU,
// not the moment the host happened to wait. VDBFUSE_CUDA_SYNC=1 restores a wait after every
// launch (a fault is then reported naming its kernel).
#include <cuda_runtime.h>

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

// The rows of f over [0, n), summed by the `blocks` blocks that share a grid-stride loop (this
// one is number `block`), into one partial row of N floats.
template <int N, class F>
__device__ void reduceBlockRows(int n, const F& f, unsigned block, unsigned blocks, float* partial_row) {
  float acc[N];
#pragma unroll
  for (int k = 0; k < N; ++k) acc[k] = 0.f;
  float row[N];
  const unsigned stride = blocks * blockDim.x;
  for (unsigned i = block * blockDim.x + threadIdx.x; i < unsigned(n); i += stride) {
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
    partial_row[k] = s;
  }
}

// One partial row per block: partials[blockIdx.x * N + k].
template <int N, class F>
__global__ void __launch_bounds__(kBlockThreads) reduceRowsKernel(int n, F f, float* partials) {
  reduceBlockRows<N>(n, f, blockIdx.x, gridDim.x, partials + size_t(blockIdx.x) * N);
}

// Two reductions in one launch: blocks [0, f_blocks) reduce f exactly as reduceRowsKernel with
// f_blocks blocks would, the rest reduce g; the partial rows of g follow those of f. (The same
// grid per reduction, and so the same sums bit for bit, as two launches.)
template <int N, class F, class G>
__global__ void __launch_bounds__(kBlockThreads)
    reduceTwoRowsKernel(int n_f, F f, int f_blocks, int n_g, G g, float* partials) {
  if (int(blockIdx.x) < f_blocks)
    reduceBlockRows<N>(n_f, f, blockIdx.x, unsigned(f_blocks), partials + size_t(blockIdx.x) * N);
  else
    reduceBlockRows<N>(n_g, g, blockIdx.x - unsigned(f_blocks), gridDim.x - unsigned(f_blocks),
                       partials + size_t(blockIdx.x) * N);
}

inline int reduceBlocks(int n) {
  const int blocks = (n + kBlockThreads - 1) / kBlockThreads;
  return blocks < kMaxReduceBlocks ? blocks : kMaxReduceBlocks;
}

template <class F>
void parallelFor(int n, const F& f) {
  if (n <= 0) return;
  const int blocks = (n + kBlockThreads - 1) / kBlockThreads;
  forEachKernel<F><<<blocks < kMaxForBlocks ? blocks : kMaxForBlocks, kBlockThreads>>>(n, f);
  detail::check(cudaGetLastError(), "launch of ", __PRETTY_FUNCTION__);
  if (waitsAfterEachLaunch()) detail::check(cudaDeviceSynchronize(), "kernel ", __PRETTY_FUNCTION__);
}

template <int N, class F>
void parallelReduce(int n, const F& f, double* out) {
  for (int k = 0; k < N; ++k) out[k] = 0.0;
  if (n <= 0) return;
  const int blocks = reduceBlocks(n);
  detail::ReduceScratch scratch(size_t(kMaxReduceBlocks) * N, size_t(N));
  reduceRowsKernel<N, F><<<blocks, kBlockThreads>>>(n, f, scratch.partials());
  detail::check(cudaGetLastError(), "launch of ", __PRETTY_FUNCTION__);
  scratch.sumToHost(blocks, N, out, __PRETTY_FUNCTION__);
}

// f's and g's sums with one launch and one wait for the GPU (tracking's geometric and photometric
// rows at one pose: half the round trips of an ICP iteration).
template <int N, class F, class G>
void parallelReduceTwo(int n_f, const F& f, int n_g, const G& g, double* out_f, double* out_g) {
  for (int k = 0; k < N; ++k) out_f[k] = out_g[k] = 0.0;
  if (n_f <= 0 || n_g <= 0) {  // one of them is empty: one reduction
    if (n_f > 0) parallelReduce<N>(n_f, f, out_f);
    if (n_g > 0) parallelReduce<N>(n_g, g, out_g);
    return;
  }
  const int f_blocks = reduceBlocks(n_f), g_blocks = reduceBlocks(n_g);
  detail::ReduceScratch scratch(size_t(2 * kMaxReduceBlocks) * N, size_t(2 * N));
  reduceTwoRowsKernel<N, F, G><<<f_blocks + g_blocks, kBlockThreads>>>(n_f, f, f_blocks, n_g, g, scratch.partials());
  detail::check(cudaGetLastError(), "launch of ", __PRETTY_FUNCTION__);
  scratch.sumTwoToHost(f_blocks, g_blocks, N, out_f, out_g, __PRETTY_FUNCTION__);
}

}  // namespace vf::cuda
