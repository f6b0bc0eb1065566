// The memory checks reconstruct runs before it reserves the volume (src/app/memory_check.h).
#include <gtest/gtest.h>

#include "app/memory_check.h"
#include "core/error.h"
#include "test_data.h"

namespace vf::app {
namespace {

constexpr uint64_t kGiB = uint64_t(1) << 30;

TEST(HostMemoryCheck, RefusesMoreThanRamPlusSwapAndWarnsAboveAvailable) {
  const HostMemory memory{16 * kGiB, 6 * kGiB, 2 * kGiB};
  EXPECT_EQ(checkVolumeFits(5 * kGiB, memory, "512x512x512 voxels"), "");
  const std::string warning = checkVolumeFits(8 * kGiB, memory, "1024x512x512 voxels");
  EXPECT_NE(warning.find("warning: the volume (1024x512x512 voxels) needs up to 8.0 GiB"), std::string::npos) << warning;
  EXPECT_NE(warning.find("6.0 GiB available"), std::string::npos) << warning;
  const std::string error = test::errorOf([&] { checkVolumeFits(19 * kGiB, memory, "1024x1024x512 voxels"); });
  EXPECT_NE(error.find("needs up to 19.0 GiB of host memory"), std::string::npos) << error;
  EXPECT_NE(error.find("16.0 GiB RAM + 2.0 GiB swap"), std::string::npos) << error;
  EXPECT_NE(error.find("lower --volume-size"), std::string::npos) << error;
}

TEST(GpuMemoryCheck, RefusesMoreThanTheGpuHasFreeAndSaysWhatLowersIt) {
  const GpuMemory gpu{10 * kGiB, 80 * kGiB};
  EXPECT_NO_THROW(checkVolumeFitsGpu(10 * kGiB, gpu, "1024x1024x1024 voxels"));
  const std::string error = test::errorOf([&] { checkVolumeFitsGpu(10 * kGiB + 1, gpu, "1024x1024x1024 voxels"); });
  EXPECT_NE(error.find("the volume (1024x1024x1024 voxels) needs 10.0 GiB of GPU memory, the GPU has 10.0 GiB free "
                       "of 80.0 GiB"),
            std::string::npos)
      << error;
  EXPECT_NE(error.find("--voxel-size-m"), std::string::npos) << error;
  EXPECT_NE(error.find("--device cpu"), std::string::npos) << error;
}

TEST(HostMemoryCheck, ReadsThisMachinesMeminfo) {
  const std::optional<HostMemory> memory = readHostMemory();
  ASSERT_TRUE(memory.has_value()) << "/proc/meminfo could not be read";
  EXPECT_GT(memory->total_bytes, uint64_t(256) << 20);
  EXPECT_LE(memory->available_bytes, memory->total_bytes);
}

}  // namespace
}  // namespace vf::app
