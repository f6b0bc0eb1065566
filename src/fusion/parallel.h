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
#include <type_traits>
#include <utility>
#include <vector>

#include "core/error.h"
#include "fusion/cuda_api.h"
#include "fusion/device.h"

namespace vf {

// A per-pixel functor may also define `VF_HD int rowLength() const` and `VF_HD void at(int x,
// int y, int i) const` for element i = y * rowLength() + x, its operator()(i) calling at(i %
// rowLength(), i / rowLength(), i): the CPU then walks whole rows and spends no integer division
// per pixel; CUDA threads keep operator().
template <class F, class = void>
struct HasRowWalk : std::false_type {};
template <class F>
struct HasRowWalk<F, std::void_t<decltype(std::declval<const F&>().rowLength()),
                                 decltype(std::declval<const F&>().at(0, 0, 0))>> : std::true_type {};

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
  if constexpr (HasRowWalk<F>::value) {
    const int width = f.rowLength();
    tbb::parallel_for(tbb::blocked_range<int>(0, n, 1024), [&](const tbb::blocked_range<int>& r) {
      int y = r.begin() / width, x = r.begin() - y * width;
      for (int i = r.begin(); i < r.end(); x = 0, ++y) {
        const int row_end = std::min(r.end(), i + (width - x));
        for (; i < row_end; ++i, ++x) f.at(x, y, i);
      }
    });
    return;
  }
  tbb::parallel_for(tbb::blocked_range<int>(0, n, 1024), [&](const tbb::blocked_range<int>& r) {
    for (int i = r.begin(); i != r.end(); ++i) f(i);
  });
}

// A parallelReduce kernel may also evaluate kReduceLanes elements at once, `template <int L>
// VF_HD bool rows(int first, int n, float (&row)[N][L]) const` (row[k][lane], zero for the
// elements from n on; false: all rows zero), written so that the CPU compiler runs the lanes in
// vector registers. The CPU reduction then uses it and sums lane by lane; CUDA keeps one
// element per thread.
constexpr int kReduceLanes = 8;
template <class F, int N, class = void>
struct HasReduceLanes : std::false_type {};
template <class F, int N>
struct HasReduceLanes<F, N,
                      std::void_t<decltype(std::declval<const F&>().template rows<kReduceLanes>(
                          0, 0, std::declval<float (&)[N][kReduceLanes]>()))>> : std::true_type {};

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
      const int end = std::min(n, (c + 1) * kChunk);
      if constexpr (HasReduceLanes<F, N>::value) {
        static_assert(kChunk % kReduceLanes == 0, "a chunk holds whole groups of lanes");
        // 32 groups (256 elements) per lane in float, then into double, as below.
        float chunk[N][kReduceLanes] = {};
        float rows[N][kReduceLanes];
        int groups = 0;
        for (int i = c * kChunk; i < end; i += kReduceLanes) {
          if (!f.template rows<kReduceLanes>(i, n, rows)) continue;
          for (int k = 0; k < N; ++k)
            for (int j = 0; j < kReduceLanes; ++j) chunk[k][j] += rows[k][j];
          if (++groups == 256 / kReduceLanes) {
            for (int k = 0; k < N; ++k)
              for (int j = 0; j < kReduceLanes; ++j) acc[k] += chunk[k][j], chunk[k][j] = 0.f;
            groups = 0;
          }
        }
        for (int k = 0; k < N; ++k)
          for (int j = 0; j < kReduceLanes; ++j) acc[k] += chunk[k][j];
        continue;
      }
      float row[N];
      // Accumulate 256 rows in float (fast), then fold into double.
      float chunk[N] = {};
      int in_chunk = 0;
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

// Two reductions of rows of one size, e.g. tracking's geometric and photometric rows at one
// pose. The results are those of two parallelReduce calls, bit for bit; on the GPU they take one
// launch and one wait instead of two (each wait is a round trip the frame pays for), on the CPU
// they simply run one after the other.
template <int N, class F, class G>
std::pair<std::array<double, N>, std::array<double, N>> parallelReduceTwo(Device device, int n_f, const F& f, int n_g,
                                                                          const G& g) {
  if (device == Device::Cuda) {
#ifdef VDBFUSE_WITH_CUDA
    std::pair<std::array<double, N>, std::array<double, N>> sums;
    cuda::parallelReduceTwo<N>(n_f, f, n_g, g, sums.first.data(), sums.second.data());
    return sums;
#else
    throw Error("CUDA backend requested but vdbfuse was built without CUDA");
#endif
  }
  return {parallelReduce<N>(device, n_f, f), parallelReduce<N>(device, n_g, g)};
}

}  // namespace vf
