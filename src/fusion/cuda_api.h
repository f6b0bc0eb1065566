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
// Work is queued in order on one stream (the default one); the host waits only where it reads a
// result back (copyToHost, parallelReduce), so a launch returns before its kernel has run and a
// kernel's fault is reported by the next call that waits. VDBFUSE_CUDA_SYNC=1 in the environment
// makes every launch wait and name its kernel in an error instead (debugging; timing the old way).
bool waitsAfterEachLaunch();

// Points in the stream of work, for timing stages on the GPU's own clock (fusion/stage_timer.h).
void* createEvent();                        // throws vf::Error
void recordEvent(void* event);              // marks "everything queued so far"
bool eventReached(void* event);             // without waiting
float elapsedMs(void* start, void* end);    // waits for end
void destroyEvent(void* event) noexcept;
// Free and total memory of the current device; false where the query fails (no GPU, no driver).
bool memoryInfo(size_t* free_bytes, size_t* total_bytes) noexcept;

template <class F>
void parallelFor(int n, const F& f);

// Sums the N-float rows produced by f over i in [0, n) into out (double precision on the host).
template <int N, class F>
void parallelReduce(int n, const F& f, double* out);

// Both reductions with one launch and one wait for the GPU: out_f and out_g as two
// parallelReduce calls give them, bit for bit.
template <int N, class F, class G>
void parallelReduceTwo(int n_f, const F& f, int n_g, const G& g, double* out_f, double* out_g);

}  // namespace vf::cuda
