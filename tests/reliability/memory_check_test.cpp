// Memory checks: the GPU start-up check reconstruct runs before CUDA allocates
// (src/app/memory_check.h) and this machine's memory as the brick pool reads it (core/host_memory.h).
#include <gtest/gtest.h>

#include "app/memory_check.h"
#include "core/error.h"
#include "core/host_memory.h"
#include "test_data.h"

namespace vf::app {
namespace {

constexpr uint64_t kGiB = uint64_t(1) << 30;

TEST(GpuMemoryCheck, RefusesMoreThanTheGpuHasFreeAndSaysWhatToDo) {
  const GpuMemory gpu{10 * kGiB, 80 * kGiB};
  EXPECT_NO_THROW(checkFitsGpu(10 * kGiB, gpu, "fusing teddy (640x480)"));
  const std::string error = test::errorOf([&] { checkFitsGpu(10 * kGiB + 1, gpu, "fusing teddy (640x480)"); });
  EXPECT_NE(error.find("fusing teddy (640x480) needs 10.0 GiB of GPU memory to start, the GPU has 10.0 GiB free "
                       "of 80.0 GiB"),
            std::string::npos)
      << error;
  EXPECT_NE(error.find("--device cpu"), std::string::npos) << error;
}

// Issue 35 cause 14: running out of memory named no option.
TEST(OutOfMemory, ReconstructNamesTheOptionsThatLowerTheNeed) {
  const std::string message = outOfMemoryMessage("reconstruct");
  for (const char* option : {"--voxel-size-m", "--max-depth-m", "--max-frames", "ulimit -v"})
    EXPECT_NE(message.find(option), std::string::npos) << message;
  EXPECT_EQ(outOfMemoryMessage("mesh"), "out of memory (an input states sizes this machine cannot hold)");
}

TEST(HostMemory, ReadsThisMachinesMeminfo) {
  const std::optional<HostMemory> memory = readHostMemory();
  ASSERT_TRUE(memory.has_value()) << "/proc/meminfo could not be read";
  EXPECT_GT(memory->total_bytes, uint64_t(256) << 20);
  EXPECT_LE(memory->available_bytes, memory->total_bytes);
}

}  // namespace
}  // namespace vf::app
