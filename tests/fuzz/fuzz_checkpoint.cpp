// Fuzz target: a reconstruction checkpoint as `reconstruct --resume` reads it. The input is the
// file without its closing checksum, which the target appends: a checksum only tells a damaged
// file from a whole one, so the fields behind it must hold against a file forged whole (a NaN pose
// resumed and wrote a trajectory of nan). The pipeline is the one the seeds were written for
// (corpus/checkpoint, made by make_seeds.py): 64x48 camera, 2 cm voxels, 10 cm truncation.
#include <cmath>
#include <cstring>
#include <vector>

#include "core/error.h"
#include "fusion/checkpoint.h"
#include "fusion/pipeline.h"
#include "fuzz/fuzz_util.h"

namespace {

uint64_t fnv1a(const uint8_t* p, size_t n) {
  uint64_t h = 1469598103934665603ull;
  for (size_t i = 0; i < n; ++i) h = (h ^ p[i]) * 1099511628211ull;
  return h;
}

// The class flag follows the magic (16), the version (4), the settings and two floats.
bool fusedWithClasses(const std::vector<uint8_t>& file, const vf::RunSettings& settings) {
  size_t at = 16 + 4 + 4;
  for (const auto& [key, value] : settings) at += 4 + key.size() + 4 + value.size();
  at += 8;
  return at < file.size() && file[at] != 0;
}

bool rigidAndFinite(const vf::Pose& p) {
  if (!p.matrix().allFinite()) return false;
  const Eigen::Matrix3d R = p.linear();
  return (R.transpose() * R - Eigen::Matrix3d::Identity()).cwiseAbs().maxCoeff() < 1e-5;
}

}  // namespace

extern "C" int LLVMFuzzerTestOneInput(const uint8_t* data, size_t size) {
  std::vector<uint8_t> file(data, data + size);
  const uint64_t sum = fnv1a(file.data(), file.size());
  file.resize(size + sizeof sum);
  std::memcpy(file.data() + size, &sum, sizeof sum);
  const std::string path = vf::fuzz::writeTempInput("_run.checkpoint", file.data(), file.size());
  try {
    const vf::RunSettings settings = vf::readCheckpointSettings(path);
    vf::PipelineParams params;
    params.volume.voxel_size_m = 0.02f;
    params.volume.truncation_m = 0.1f;
    const vf::Intrinsics camera{60.f, 60.f, 32.f, 24.f, 64, 48};
    vf::Pipeline pipeline(params, camera, vf::Device::Cpu, fusedWithClasses(file, settings));
    const vf::RunProgress progress = vf::readCheckpoint(path, pipeline, settings);
    // Documented: what a checkpoint restores is what a run can produce. (Lost frames have no
    // pose, and the second pass starts counting again over a whole trajectory, so the trajectory
    // may be shorter or longer than the frames done.)
    if (progress.frames_done < 0 || progress.lost.size() > size_t(progress.frames_done)) std::abort();
    for (const vf::StampedPose& p : progress.trajectory)
      if (!std::isfinite(p.timestamp) || !rigidAndFinite(p.T_world_cam)) std::abort();
    if (!rigidAndFinite(pipeline.state().T_world_cam) || !rigidAndFinite(pipeline.state().T_world_model)) std::abort();
  } catch (const vf::Error&) {
  }
  return 0;
}
