#pragma once
// Runs a per-element functor (a struct with `VF_HD void operator()(int i) const`) on the chosen
// backend. The functor is the single definition of the rule; TBB and CUDA merely iterate it.
// A work item may cover several elements where that pays on the CPU (RaycastKernel's
// rays_per_item, MarkBricksKernel's tile_px): the host sets the count from the device, and no
// element's result depends on it.
#include <tbb/blocked_range.h>
#include <tbb/parallel_for.h>

#include <algorithm>
#include <array>
#include <vector>

#include "core/error.h"
#include "fusion/cuda_api.h"
#include "fusion/device.h"

namespace vf {

template <class F>
void parallelFor(Device device, int n, const F& f) {
  if (n <= 0) return;
  if (device == Device::Cuda) {
#ifdef VDBFUSE_WITH_CUDA
    cuda::parallelFor(n, f);
    return;
#else
    throw Error("CUDA backend requested but vdbfuse was built without CUDA");
#endif
  }
  tbb::parallel_for(tbb::blocked_range<int>(0, n, 1024), [&](const tbb::blocked_range<int>& r) {
    for (int i = r.begin(); i != r.end(); ++i) f(i);
  });
}

// Reduction of fixed-size float rows: f is `VF_HD bool operator()(int i, float* row) const`
// returning false when element i contributes nothing. The CPU sum is deterministic: the range is
// cut into fixed chunks (independent of the thread count and of TBB's work stealing), each chunk
// is summed on its own, and the chunk sums are added in order. ICP poses, and so the fused
// volume, are then bit-identical from run to run (checkpoint/resume relies on it).
template <int N, class F>
std::array<double, N> parallelReduce(Device device, int n, const F& f) {
  std::array<double, N> total{};
  if (n <= 0) return total;
  if (device == Device::Cuda) {
#ifdef VDBFUSE_WITH_CUDA
    cuda::parallelReduce<N>(n, f, total.data());
    return total;
#else
    throw Error("CUDA backend requested but vdbfuse was built without CUDA");
#endif
  }
  constexpr int kChunk = 4096;
  const int chunks = (n + kChunk - 1) / kChunk;
  std::vector<std::array<double, N>> partial(size_t(chunks), std::array<double, N>{});
  tbb::parallel_for(tbb::blocked_range<int>(0, chunks, 1), [&](const tbb::blocked_range<int>& r) {
    for (int c = r.begin(); c != r.end(); ++c) {
      std::array<double, N>& acc = partial[size_t(c)];
      float row[N];
      // Accumulate 256 rows in float (fast), then fold into double.
      float chunk[N] = {};
      int in_chunk = 0;
      const int end = std::min(n, (c + 1) * kChunk);
      for (int i = c * kChunk; i != end; ++i) {
        if (!f(i, row)) continue;
        for (int k = 0; k < N; ++k) chunk[k] += row[k];
        if (++in_chunk == 256) {
          for (int k = 0; k < N; ++k) acc[k] += chunk[k], chunk[k] = 0.f;
          in_chunk = 0;
        }
      }
      for (int k = 0; k < N; ++k) acc[k] += chunk[k];
    }
  });
  for (const std::array<double, N>& p : partial)
    for (int k = 0; k < N; ++k) total[k] += p[k];
  return total;
}

}  // namespace vf
