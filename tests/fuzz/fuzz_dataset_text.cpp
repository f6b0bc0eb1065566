// Fuzz target: the text files of the dataset layouts (io/dataset_text.h): 4x4 pose files,
// Replica traj.txt, Redwood .log trajectories and intrinsic matrices, all parsed from one input.
#include <cmath>
#include <string>

#include "core/error.h"
#include "io/dataset_text.h"

namespace {

void checkPose(const vf::Pose& p) {
  if (!p.matrix().allFinite()) std::abort();
  if ((p.linear().transpose() * p.linear() - Eigen::Matrix3d::Identity()).cwiseAbs().maxCoeff() > 1e-9) std::abort();
}

template <class F>
void guarded(F&& f) {
  try {
    f();
  } catch (const vf::Error&) {
  }
}

}  // namespace

extern "C" int LLVMFuzzerTestOneInput(const uint8_t* data, size_t size) {
  const std::string text(reinterpret_cast<const char*>(data), size);
  guarded([&] {
    const std::vector<double> v = vf::parseNumbers(text, "pose.txt");
    if (v.size() == 16)
      if (const std::optional<vf::Pose> p = vf::poseFromRowMajor(v.data(), "pose.txt")) checkPose(*p);
  });
  guarded([&] {
    const std::vector<vf::Pose> poses = vf::parseReplicaTrajectory(text, "traj.txt");
    if (poses.empty()) std::abort();  // documented: no pose is an error
    for (const vf::Pose& p : poses) checkPose(p);
  });
  guarded([&] {
    const std::vector<vf::LogEntry> entries = vf::parseLogTrajectory(text, "trajectory.log");
    if (entries.empty()) std::abort();
    for (const vf::LogEntry& e : entries) {
      if (e.frame < 0) std::abort();
      checkPose(e.T_world_cam);
    }
  });
  guarded([&] {
    const vf::PinholeMatrix k = vf::parseIntrinsicMatrix(text, "camera-intrinsics.txt");
    if (!(k.fx > 0 && k.fy > 0) || !std::isfinite(k.cx) || !std::isfinite(k.cy)) std::abort();
  });
  return 0;
}
