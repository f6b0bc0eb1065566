// The CUDA backend's memory layer: device buffers hold what was uploaded, copies and fills do
// what they say, failures throw vf::Error naming the CUDA call and leave the GPU usable, and a
// machine without a GPU says why instead of crashing.
#include <gtest/gtest.h>

#include "cuda/require_gpu.h"

#include <numeric>
#include <string>
#include <vector>

#include "core/error.h"
#include "fusion/buffer.h"
#include "fusion/cuda_api.h"
#include "fusion/device.h"
#include "fusion/stage_timer.h"

namespace vf {
namespace {

bool contains(const std::string& text, const std::string& part) { return text.find(part) != std::string::npos; }

// Runs where there is no GPU (CI, this builder): the CPU path must stand alone.
TEST(CudaDiscovery, WithoutAGpuTheReasonIsReportedAndCudaRequestsFailWithAnError) {
  if (cudaDeviceCount() > 0) GTEST_SKIP() << "a CUDA GPU is present; this checks the no-GPU path";
  EXPECT_TRUE(cudaBuilt());
  const std::string reason = cuda::lastErrorDescription();
  EXPECT_FALSE(reason.empty());
  EXPECT_EQ(resolveDevice(Device::Auto), Device::Cpu);
  try {
    resolveDevice(Device::Cuda);
    ADD_FAILURE() << "resolveDevice(Cuda) did not throw without a GPU";
  } catch (const Error& e) {
    EXPECT_TRUE(contains(e.what(), reason)) << e.what();
    EXPECT_TRUE(contains(e.what(), "Device = cpu runs without one")) << e.what();  // the app adds "(--device)"
  }
  // Direct use of the backend throws vf::Error (never exit()).
  try {
    void* p = cuda::allocate(1024);
    cuda::release(p);
    ADD_FAILURE() << "cuda::allocate succeeded without a GPU";
  } catch (const Error& e) {
    EXPECT_TRUE(contains(e.what(), "cudaMalloc")) << e.what();
  }
  cuda::release(nullptr);  // harmless
  uint64_t free_bytes = 1, total_bytes = 1;
  EXPECT_FALSE(cudaMemoryInfo(free_bytes, total_bytes));  // reconstruct then checks host memory only
}

TEST(CudaDiscovery, WithAGpuThereIsNoErrorToReport) {
  VF_REQUIRE_GPU();
  EXPECT_GT(cudaDeviceCount(), 0);
  EXPECT_EQ(cuda::lastErrorDescription(), "");
  EXPECT_EQ(resolveDevice(Device::Auto), Device::Cuda);
}

// reconstruct's GPU memory check (app/memory_check.h) compares the volume with this.
TEST(CudaDiscovery, MemoryInfoSeesAnAllocation) {
  VF_REQUIRE_GPU();
  uint64_t free_before = 0, total = 0;
  ASSERT_TRUE(cudaMemoryInfo(free_before, total));
  EXPECT_GT(total, uint64_t(1) << 30);
  EXPECT_LE(free_before, total);
  const size_t bytes = size_t(512) << 20;
  Buffer<uint8_t> buffer(Device::Cuda, bytes);
  uint64_t free_after = 0;
  ASSERT_TRUE(cudaMemoryInfo(free_after, total));
  EXPECT_LE(free_after + bytes, free_before);
}

TEST(CudaBuffer, FreshBufferIsZeroAndHoldsWhatWasUploaded) {
  VF_REQUIRE_GPU();
  const size_t n = 100003;  // not a multiple of anything convenient
  Buffer<int> buffer(Device::Cuda, n);
  ASSERT_NE(buffer.data(), nullptr);
  std::vector<int> host(n, -1);
  buffer.download(host.data(), n);
  for (size_t i = 0; i < n; ++i) ASSERT_EQ(host[i], 0) << "at " << i;
  std::iota(host.begin(), host.end(), 7);
  buffer.upload(host.data(), n);
  std::vector<int> back(n, 0);
  buffer.download(back.data(), n);
  EXPECT_EQ(back, host);
  buffer.zero();
  buffer.download(back.data(), n);
  EXPECT_EQ(back, std::vector<int>(n, 0));
}

TEST(CudaBuffer, CopyOnDeviceAndPartialTransfers) {
  VF_REQUIRE_GPU();
  Buffer<float> a(Device::Cuda, 1000), b(Device::Cuda, 1000);
  std::vector<float> host(1000);
  for (int i = 0; i < 1000; ++i) host[size_t(i)] = 0.5f * float(i);
  a.upload(host.data(), 1000);
  cuda::copyOnDevice(b.data(), a.data(), 1000 * sizeof(float));
  std::vector<float> back(1000, -1.f);
  b.download(back.data(), 1000);
  EXPECT_EQ(back, host);
  // The first 10 elements only.
  std::vector<float> ten(10, 0.f);
  b.download(ten.data(), 10);
  for (int i = 0; i < 10; ++i) EXPECT_EQ(ten[size_t(i)], 0.5f * float(i));
  EXPECT_THROW(b.download(back.data(), 1001), Error);
  EXPECT_THROW(b.upload(host.data(), 1001), Error);
}

// Uploads are queued from pinned staging slots (cuda/memory.cu) and the host goes on at once:
// more uploads in a row than there are slots, the host's array rewritten between them, must each
// arrive whole; and of several uploads to one buffer the last one stays.
TEST(CudaBuffer, UploadsQueuedInARowArriveIntact) {
  VF_REQUIRE_GPU();
  constexpr int kBuffers = 24;  // three times the staging slots
  const size_t n = 300007;
  std::vector<Buffer<int>> buffers;
  for (int b = 0; b < kBuffers; ++b) buffers.emplace_back(Device::Cuda, n);
  std::vector<int> host(n);
  for (int b = 0; b < kBuffers; ++b) {
    for (size_t i = 0; i < n; ++i) host[i] = b * 1000003 + int(i);
    buffers[size_t(b)].upload(host.data(), n);
  }
  for (int round = 0; round < 20; ++round) {
    std::fill(host.begin(), host.end(), round);
    buffers[0].upload(host.data(), n);
  }
  std::vector<int> back(n);
  buffers[0].download(back.data(), n);
  EXPECT_EQ(back, std::vector<int>(n, 19));
  for (int b = 1; b < kBuffers; ++b) {
    buffers[size_t(b)].download(back.data(), n);
    for (size_t i = 0; i < n; ++i) ASSERT_EQ(back[i], b * 1000003 + int(i)) << "buffer " << b << " at " << i;
  }
}

// A GPU stage is timed on the GPU's clock between two events (fusion/stage_timer.h), not by when
// the host got back: the copies below return before the GPU has done them.
TEST(CudaStageTimer, AGpuStageIsTimedByTheEventsAroundItsWork) {
  VF_REQUIRE_GPU();
  StageTimer timer;
  const size_t bytes = size_t(256) << 20;
  Buffer<char> a(Device::Cuda, bytes), b(Device::Cuda, bytes);
  for (int i = 0; i < 3; ++i) {
    ScopedStage stage(timer, "copy", Device::Cuda);
    cuda::copyOnDevice(b.data(), a.data(), bytes);
  }
  ASSERT_EQ(timer.stages(), std::vector<std::string>{"copy"});
  const std::vector<double> samples = timer.samples("copy");
  ASSERT_EQ(samples.size(), 3u);
  for (double ms : samples) {
    EXPECT_GT(ms, 0.02) << "512 MiB read and written cannot take less";
    EXPECT_LT(ms, 2000.0);
  }
  const StageTimer copy = timer;  // the samples, no events
  EXPECT_EQ(copy.samples("copy"), samples);
}

TEST(CudaBuffer, MoveTransfersOwnershipAndResetFreesIt) {
  VF_REQUIRE_GPU();
  Buffer<int> a(Device::Cuda, 64);
  std::vector<int> host(64);
  std::iota(host.begin(), host.end(), 1);
  a.upload(host.data(), 64);
  int* const ptr = a.data();
  Buffer<int> b(std::move(a));
  EXPECT_EQ(a.data(), nullptr);
  EXPECT_EQ(a.size(), 0u);
  EXPECT_EQ(b.data(), ptr);
  EXPECT_EQ(b.device(), Device::Cuda);
  std::vector<int> back(64);
  b.download(back.data(), 64);
  EXPECT_EQ(back, host);
  Buffer<int> c;
  c = std::move(b);
  EXPECT_EQ(c.data(), ptr);
  c.reset();
  EXPECT_EQ(c.data(), nullptr);
  // Many allocate/free cycles of a large buffer: a leak would exhaust the GPU.
  for (int i = 0; i < 200; ++i) Buffer<char> big(Device::Cuda, size_t(1) << 30);
}

TEST(CudaErrors, AnImpossibleAllocationThrowsNamingTheCallAndTheGpuStaysUsable) {
  VF_REQUIRE_GPU();
  try {
    void* p = cuda::allocate(size_t(1) << 50);  // 1 PiB
    cuda::release(p);
    ADD_FAILURE() << "a 1 PiB cudaMalloc succeeded";
  } catch (const Error& e) {
    EXPECT_TRUE(contains(e.what(), "cudaMalloc")) << e.what();
    EXPECT_TRUE(contains(e.what(), "MiB free")) << e.what();
  }
  // The error was not sticky: the next allocation and copy work.
  Buffer<int> ok(Device::Cuda, 16);
  const int value = 42;
  ok.upload(&value, 1);
  int back = 0;
  ok.download(&back, 1);
  EXPECT_EQ(back, 42);
}

TEST(CudaErrors, ACopyToANullDevicePointerThrowsNamingTheCall) {
  VF_REQUIRE_GPU();
  const int value = 1;
  try {
    cuda::copyToDevice(nullptr, &value, sizeof(value));
    ADD_FAILURE() << "cudaMemcpy to nullptr succeeded";
  } catch (const Error& e) {
    EXPECT_TRUE(contains(e.what(), "cudaMemcpy")) << e.what();
  }
  EXPECT_NO_THROW(cuda::synchronize());
}

}  // namespace
}  // namespace vf
