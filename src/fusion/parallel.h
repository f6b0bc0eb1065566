#pragma once
// Runs a per-element functor (a struct with `VF_HD void operator()(int i) const`) on the chosen
// backend. The functor is the single definition of the rule; TBB and CUDA merely iterate it.
#include <tbb/blocked_range.h>
#include <tbb/parallel_for.h>
#include <tbb/parallel_reduce.h>

#include <array>

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
// returning false when element i contributes nothing. Partial sums are kept in double so the
// result does not depend on how the range was split beyond rounding of the last bits.
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
  return tbb::parallel_reduce(
      tbb::blocked_range<int>(0, n, 4096), total,
      [&](const tbb::blocked_range<int>& r, std::array<double, N> acc) {
        float row[N];
        // Accumulate a chunk in float (fast), then fold into double.
        float chunk[N] = {};
        int in_chunk = 0;
        for (int i = r.begin(); i != r.end(); ++i) {
          if (!f(i, row)) continue;
          for (int k = 0; k < N; ++k) chunk[k] += row[k];
          if (++in_chunk == 256) {
            for (int k = 0; k < N; ++k) acc[k] += chunk[k], chunk[k] = 0.f;
            in_chunk = 0;
          }
        }
        for (int k = 0; k < N; ++k) acc[k] += chunk[k];
        return acc;
      },
      [](std::array<double, N> a, const std::array<double, N>& b) {
        for (int k = 0; k < N; ++k) a[k] += b[k];
        return a;
      });
}

}  // namespace vf
