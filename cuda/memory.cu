// Device memory, copies and device discovery for the CUDA backend (fusion/cuda_api.h).
// Every failing CUDA call throws vf::Error naming the call and CUDA's message; deviceCount() is
// the one exception: it answers 0 and remembers why, so that callers can fall back to the CPU.
#include <algorithm>
#include <array>
#include <cstdlib>
#include <cstring>
#include <mutex>
#include <string>
#include <vector>

#include "check.h"
#include "core/error.h"
#include "fusion/cuda_api.h"

namespace vf::cuda {
namespace detail {

void check(cudaError_t status, const std::string& call) {
  if (status == cudaSuccess) return;
  (void)cudaGetLastError();  // clear a non-sticky error; a sticky one stays (the context is lost)
  throw Error(std::string("CUDA ") + call + " failed: " + cudaGetErrorName(status) + " (" +
              cudaGetErrorString(status) + ")");
}

namespace {

// A kernel compiled like every fusion kernel: if it has no image for the GPU's architecture,
// neither have they, and the GPU is reported unusable instead of failing at the first launch.
__global__ void probeKernel() {}

struct Discovery {
  int count = 0;
  std::string reason;
};

Discovery discover() {
  Discovery d;
  int count = 0;
  cudaError_t status = cudaGetDeviceCount(&count);
  if (status != cudaSuccess) {
    (void)cudaGetLastError();
    int driver = 0, runtime = 0;
    (void)cudaDriverGetVersion(&driver);  // 0 when no driver (libcuda.so) is installed
    (void)cudaRuntimeGetVersion(&runtime);
    (void)cudaGetLastError();
    const auto version = [](int v) { return std::to_string(v / 1000) + "." + std::to_string(v % 1000 / 10); };
    if (driver == 0)
      d.reason = "no NVIDIA driver is installed (";
    else if (driver < runtime)
      d.reason = "the NVIDIA driver supports CUDA " + version(driver) + ", this build needs " + version(runtime) + " (";
    else
      d.reason = "the CUDA driver found no usable GPU (";
    d.reason += std::string("cudaGetDeviceCount: ") + cudaGetErrorName(status) + ")";
    return d;
  }
  if (count == 0) {
    d.reason = "the CUDA driver reports no GPU";
    return d;
  }
  cudaFuncAttributes attributes;
  status = cudaFuncGetAttributes(&attributes, probeKernel);
  if (status != cudaSuccess) {
    (void)cudaGetLastError();
    cudaDeviceProp prop{};
    const bool have_prop = cudaGetDeviceProperties(&prop, 0) == cudaSuccess;
    d.reason = std::string("GPU 0 cannot run this build: ") + cudaGetErrorName(status) + ", " +
               cudaGetErrorString(status);
    if (have_prop)
      d.reason += " (GPU " + std::string(prop.name) + " is sm_" + std::to_string(prop.major) +
                  std::to_string(prop.minor) + "; rebuild with -DCMAKE_CUDA_ARCHITECTURES=" +
                  std::to_string(prop.major) + std::to_string(prop.minor) + ")";
    return d;
  }
  d.count = count;
  return d;
}

const Discovery& discovery() {
  static const Discovery d = discover();  // thread-safe once; the driver answer does not change
  return d;
}

}  // namespace
}  // namespace detail

int deviceCount() { return detail::discovery().count; }

std::string lastErrorDescription() {
  const detail::Discovery& d = detail::discovery();
  return d.count > 0 ? std::string() : d.reason;
}

void* allocate(size_t bytes) {
  if (bytes == 0) return nullptr;
  void* ptr = nullptr;
  const cudaError_t status = cudaMalloc(&ptr, bytes);
  if (status != cudaSuccess) {
    const std::string call = "cudaMalloc(" + std::to_string(bytes / double(1 << 20)) + " MiB)";
    size_t free_bytes = 0, total_bytes = 0;
    (void)cudaGetLastError();
    std::string extra;
    if (cudaMemGetInfo(&free_bytes, &total_bytes) == cudaSuccess)
      extra = "; " + std::to_string(free_bytes >> 20) + " of " + std::to_string(total_bytes >> 20) +
              " MiB free on the GPU (larger voxels or a shorter depth range need less)";
    (void)cudaGetLastError();
    throw Error(std::string("CUDA ") + call + " failed: " + cudaGetErrorName(status) + " (" +
                cudaGetErrorString(status) + ")" + extra);
  }
  return ptr;
}

void release(void* ptr) noexcept {
  if (!ptr) return;
  // Called from destructors, also after a sticky error or during process exit when the runtime
  // is already unloading: nothing useful can be done with a failure here.
  (void)cudaFree(ptr);
  (void)cudaGetLastError();
}

bool waitsAfterEachLaunch() {
  static const bool wait = [] {
    const char* value = std::getenv("VDBFUSE_CUDA_SYNC");
    return value && *value && std::string(value) != "0";
  }();
  return wait;
}

namespace {

// Uploads go through pinned staging buffers and cudaMemcpyAsync. A copy from pageable memory
// first waits for every kernel queued before it (CUDA's rule for pageable sources), so each
// frame's upload would drain the stream; from pinned memory it is queued like a kernel. The host
// copies the caller's bytes into a staging slot first, so the caller's memory is free again when
// copyToDevice returns, as before. Slots are used in turn; a slot waits for its previous copy
// (frames ago, in practice) before it is overwritten.
constexpr size_t kStagingSlots = 8;
constexpr size_t kMaxStagedBytes = size_t(8) << 20;  // a larger upload (a restored volume) copies directly

struct StagingSlot {
  void* host = nullptr;
  size_t capacity = 0;
  cudaEvent_t copied = nullptr;
};

struct StagingRing {
  std::mutex mutex;
  std::array<StagingSlot, kStagingSlots> slots;
  size_t next = 0;
  ~StagingRing() {  // at exit the runtime may already be unloading: failures are ignored
    for (StagingSlot& slot : slots) {
      if (slot.copied) (void)cudaEventDestroy(slot.copied);
      if (slot.host) (void)cudaFreeHost(slot.host);
    }
    (void)cudaGetLastError();
  }
};

StagingRing& stagingRing() {
  static StagingRing ring;
  return ring;
}

// A slot holding at least `bytes`, its previous copy finished; nullptr where pinned memory cannot
// be had (the caller then copies directly).
StagingSlot* stagingSlot(StagingRing& ring, size_t bytes) {
  StagingSlot& slot = ring.slots[ring.next++ % kStagingSlots];
  if (slot.copied) detail::check(cudaEventSynchronize(slot.copied), "cudaEventSynchronize (staged upload)");
  if (slot.capacity < bytes) {
    if (slot.host) (void)cudaFreeHost(slot.host);
    slot.host = nullptr;
    slot.capacity = 0;
    const size_t capacity = std::max(bytes, size_t(1) << 16);
    if (cudaHostAlloc(&slot.host, capacity, cudaHostAllocDefault) != cudaSuccess) {
      (void)cudaGetLastError();
      slot.host = nullptr;
      return nullptr;
    }
    slot.capacity = capacity;
  }
  if (!slot.copied) detail::check(cudaEventCreateWithFlags(&slot.copied, cudaEventDisableTiming), "cudaEventCreate");
  return &slot;
}

}  // namespace

void copyToDevice(void* dst, const void* src, size_t bytes) {
  if (bytes == 0) return;
  if (bytes <= kMaxStagedBytes && !waitsAfterEachLaunch()) {
    StagingRing& ring = stagingRing();
    std::lock_guard<std::mutex> lock(ring.mutex);
    if (StagingSlot* slot = stagingSlot(ring, bytes)) {
      std::memcpy(slot->host, src, bytes);
      detail::check(cudaMemcpyAsync(dst, slot->host, bytes, cudaMemcpyHostToDevice, 0), "cudaMemcpyAsync host->device");
      detail::check(cudaEventRecord(slot->copied, 0), "cudaEventRecord (staged upload)");
      return;
    }
  }
  detail::check(cudaMemcpy(dst, src, bytes, cudaMemcpyHostToDevice), "cudaMemcpy host->device");
}

void copyToHost(void* dst, const void* src, size_t bytes) {
  if (bytes == 0) return;
  detail::check(cudaMemcpy(dst, src, bytes, cudaMemcpyDeviceToHost), "cudaMemcpy device->host");
}

void copyOnDevice(void* dst, const void* src, size_t bytes) {
  if (bytes == 0) return;
  detail::check(cudaMemcpy(dst, src, bytes, cudaMemcpyDeviceToDevice), "cudaMemcpy device->device");
}

void fillZero(void* dst, size_t bytes) {
  if (bytes == 0) return;
  detail::check(cudaMemset(dst, 0, bytes), "cudaMemset");
}

void synchronize() { detail::check(cudaDeviceSynchronize(), "cudaDeviceSynchronize"); }

void* createEvent() {
  cudaEvent_t event = nullptr;
  detail::check(cudaEventCreate(&event), "cudaEventCreate");
  return event;
}

void recordEvent(void* event) { detail::check(cudaEventRecord(static_cast<cudaEvent_t>(event), 0), "cudaEventRecord"); }

bool eventReached(void* event) {
  const cudaError_t status = cudaEventQuery(static_cast<cudaEvent_t>(event));
  if (status == cudaErrorNotReady) return false;
  detail::check(status, "cudaEventQuery (a kernel queued before the event failed)");
  return true;
}

float elapsedMs(void* start, void* end) {
  detail::check(cudaEventSynchronize(static_cast<cudaEvent_t>(end)), "cudaEventSynchronize (a kernel queued before the event failed)");
  float ms = 0.f;
  detail::check(cudaEventElapsedTime(&ms, static_cast<cudaEvent_t>(start), static_cast<cudaEvent_t>(end)),
                "cudaEventElapsedTime");
  return ms;
}

void destroyEvent(void* event) noexcept {
  if (!event) return;
  (void)cudaEventDestroy(static_cast<cudaEvent_t>(event));
  (void)cudaGetLastError();
}

bool memoryInfo(size_t* free_bytes, size_t* total_bytes) noexcept {
  if (deviceCount() == 0) return false;
  if (cudaMemGetInfo(free_bytes, total_bytes) == cudaSuccess) return true;
  (void)cudaGetLastError();
  return false;
}

}  // namespace vf::cuda

// ---- reduction scratch ------------------------------------------------------------------------
namespace vf::cuda::detail {
namespace {

constexpr int kSumThreads = 128;

// Block b sums component b % n_components of the partial rows of range b / n_components (range
// 0: rows [0, first_blocks), range 1: the second_blocks rows after them) in double, in a fixed
// order (deterministic; one range sums exactly as it would alone).
__global__ void __launch_bounds__(kSumThreads) sumPartialsKernel(int first_blocks, int second_blocks, int n_components,
                                                                  const float* partials, double* sums) {
  __shared__ double s[kSumThreads];
  const int range = int(blockIdx.x) / n_components, k = int(blockIdx.x) % n_components;
  const int begin = range == 0 ? 0 : first_blocks;
  const int blocks = range == 0 ? first_blocks : second_blocks;
  double v = 0.0;
  for (int b = threadIdx.x; b < blocks; b += kSumThreads) v += double(partials[size_t(begin + b) * n_components + k]);
  s[threadIdx.x] = v;
  __syncthreads();
  for (int offset = kSumThreads / 2; offset > 0; offset >>= 1) {
    if (threadIdx.x < offset) s[threadIdx.x] += s[threadIdx.x + offset];
    __syncthreads();
  }
  if (threadIdx.x == 0) sums[size_t(range) * n_components + k] = s[0];
}

// A device array that only grows. The old one is dropped before the new allocation, so that a
// failed allocate() (which throws) leaves an empty array rather than a dangling one.
template <class T>
struct GrowingDeviceArray {
  T* data = nullptr;
  size_t capacity = 0;
  T* atLeast(size_t count) {
    if (capacity < count) {
      release(data);
      data = nullptr;
      capacity = 0;
      data = static_cast<T*>(allocate(count * sizeof(T)));
      capacity = count;
    }
    return data;
  }
};

struct ScratchStore {
  std::mutex mutex;
  GrowingDeviceArray<float> partials;
  GrowingDeviceArray<double> sums;
  ~ScratchStore() {  // at exit the runtime may already be unloading: release() ignores that
    release(partials.data);
    release(sums.data);
  }
};

ScratchStore& scratchStore() {
  static ScratchStore store;
  return store;
}

}  // namespace

ReduceScratch::ReduceScratch(size_t partial_floats, size_t sum_doubles) {
  ScratchStore& store = scratchStore();
  lock_ = std::unique_lock<std::mutex>(store.mutex);
  partials_ = store.partials.atLeast(partial_floats);
  sums_ = store.sums.atLeast(sum_doubles);
}

void ReduceScratch::sumToHost(int blocks, int n_components, double* out, const char* what) const {
  sumTwoToHost(blocks, 0, n_components, out, nullptr, what);
}

void ReduceScratch::sumTwoToHost(int first_blocks, int second_blocks, int n_components, double* out_first,
                                 double* out_second, const char* what) const {
  const int ranges = second_blocks > 0 ? 2 : 1;
  sumPartialsKernel<<<ranges * n_components, kSumThreads>>>(first_blocks, second_blocks, n_components, partials_, sums_);
  check(cudaGetLastError(), "launch of the final sum of ", what);
  // The blocking copy waits for both kernels (and everything queued before them) and reports
  // their errors.
  std::vector<double> both(ranges == 2 ? size_t(2 * n_components) : 0);
  double* const host = ranges == 2 ? both.data() : out_first;
  const cudaError_t copied =
      cudaMemcpy(host, sums_, sizeof(double) * size_t(ranges * n_components), cudaMemcpyDeviceToHost);
  if (copied != cudaSuccess) check(copied, std::string("kernel ") + what + " (or one queued before it)");
  if (ranges == 2) {
    std::copy(host, host + n_components, out_first);
    std::copy(host + n_components, host + 2 * n_components, out_second);
  }
}

}  // namespace vf::cuda::detail
