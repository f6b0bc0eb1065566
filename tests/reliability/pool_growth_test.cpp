// The CPU brick pool grows in place (mremap) and, when the address space runs out, stays full and
// says so: the run goes on fusing into the bricks it has (fusion/sparse_volume.h). A growth that
// failed after moving some arrays left the kernels with their old addresses (a segfault under
// `ulimit -v`, found by hand). Alone in its binary: the child forks before any TBB thread exists.
#include <gtest/gtest.h>
#include <sys/resource.h>
#include <sys/wait.h>
#include <unistd.h>

#include <cstdio>

#include "fusion/pipeline.h"

namespace vf {
namespace {

// A wall 2 m ahead of a 64x48 camera that moves 3 m sideways each frame: new bricks every frame.
RgbdFrame wallFrame(int index) {
  RgbdFrame frame;
  frame.name = "wall" + std::to_string(index);
  frame.timestamp = index;
  frame.depth = DepthImage(64, 48, 2.f);
  Pose pose = Pose::Identity();
  pose.translation() = Eigen::Vector3d(3.0 * index, 0, 0);
  frame.T_world_cam_given = pose;
  return frame;
}

uint64_t mappedBytes() {
  unsigned long long pages = 0;
  std::FILE* statm = std::fopen("/proc/self/statm", "r");
  if (statm && std::fscanf(statm, "%llu", &pages) != 1) pages = 0;
  if (statm) std::fclose(statm);
  return uint64_t(pages) * uint64_t(sysconf(_SC_PAGESIZE));
}

// Child: exit 0 when the pool filled up (some frame said volume_full) and every frame after it
// was still processed; 2 when it never filled, 3 when it grew past the limit.
[[noreturn]] void fuseUnderALimit() {
  PipelineParams params;
  params.volume.voxel_size_m = 0.004f;  // 3.2 cm bricks: about 3,000 new ones a frame
  const Intrinsics camera{60.f, 60.f, 32.f, 24.f, 64, 48};
  Pipeline pipeline(params, camera, Device::Cpu);
  pipeline.processFrame(wallFrame(0), PoseSource::Given);  // threads and their stacks exist now
  // Room for one array of the pool to double (16,384 bricks of 2 KiB TSDF: 32 MiB) but not two.
  const rlim_t limit = rlim_t(mappedBytes() + (uint64_t(48) << 20));
  const rlimit as{limit, limit};
  if (setrlimit(RLIMIT_AS, &as) != 0) _exit(4);
  bool full = false;
  for (int i = 1; i < 16; ++i) full = pipeline.processFrame(wallFrame(i), PoseSource::Given).volume_full || full;
  if (!full) _exit(2);
  _exit(pipeline.brickCount() <= 16384 ? 0 : 3);
}

TEST(PoolGrowth, AGrowthThatFailsLeavesAFullPoolThatStillFuses) {
  const pid_t pid = fork();
  ASSERT_GE(pid, 0);
  if (pid == 0) fuseUnderALimit();
  int status = 0;
  ASSERT_EQ(waitpid(pid, &status, 0), pid);
  ASSERT_TRUE(WIFEXITED(status)) << "the child died of signal " << WTERMSIG(status);
  EXPECT_EQ(WEXITSTATUS(status), 0) << "2: the pool never filled, 3: it grew past the limit, 4: setrlimit failed";
}

}  // namespace
}  // namespace vf
