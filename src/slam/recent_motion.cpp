#include "slam/recent_motion.h"

#include <algorithm>
#include <cmath>
#include <string>
#include <vector>

namespace vf::slam {

void RecentMotion::add(const Pose& T_world_cam, double timestamp, bool follows) {
  if (!follows || (!samples_.empty() && !(timestamp > samples_.back().timestamp))) samples_.clear();
  samples_.push_back({timestamp, T_world_cam});
  while (samples_.size() > 2 && samples_.front().timestamp < timestamp - window_s_) samples_.pop_front();
}

double RecentMotion::lastStepSeconds() const {
  if (samples_.size() < 2) return std::nan("");
  return samples_.back().timestamp - samples_[samples_.size() - 2].timestamp;
}

Pose RecentMotion::extrapolate(double timestamp, double max_speed_m_s) const {
  if (samples_.empty()) return Pose::Identity();
  const Sample& last = samples_.back();
  const double elapsed_s = timestamp - last.timestamp;
  if (samples_.size() < 2 || !(elapsed_s > 0)) return last.T_world_cam;
  // Velocities in the camera frame of each step's first pose.
  std::vector<double> rates[3];
  for (size_t i = 1; i < samples_.size(); ++i) {
    const Pose step = samples_[i - 1].T_world_cam.inverse() * samples_[i].T_world_cam;
    const double dt = samples_[i].timestamp - samples_[i - 1].timestamp;
    for (int k = 0; k < 3; ++k) rates[k].push_back(step.translation()(k) / dt);
  }
  Eigen::Vector3d velocity;
  for (int k = 0; k < 3; ++k) {
    std::vector<double>& r = rates[k];
    const size_t mid = r.size() / 2;
    std::nth_element(r.begin(), r.begin() + std::ptrdiff_t(mid), r.end());
    velocity(k) = r[mid];
    if (r.size() % 2 == 0) velocity(k) = 0.5 * (velocity(k) + *std::max_element(r.begin(), r.begin() + std::ptrdiff_t(mid)));
  }
  Eigen::Vector3d move = velocity * elapsed_s;
  const double reach_m = max_speed_m_s * elapsed_s;
  if (move.norm() > reach_m) move *= reach_m / move.norm();
  // The turn: the last step's, carried on (see the header).
  const Sample& before = samples_[samples_.size() - 2];
  const Eigen::AngleAxisd last_turn((before.T_world_cam.inverse() * last.T_world_cam).linear());
  const double steps = elapsed_s / lastStepSeconds();
  Pose step = Pose::Identity();
  step.linear() = Eigen::AngleAxisd(last_turn.angle() * steps, last_turn.axis()).toRotationMatrix();
  step.translation() = move;
  return last.T_world_cam * step;
}

void RecentMotion::write(ByteWriter& w) const {
  w.pod<uint32_t>(uint32_t(samples_.size()));
  for (const Sample& s : samples_) {
    w.pod(s.timestamp);
    w.pose(s.T_world_cam);
  }
}

void RecentMotion::read(ByteReader& in) {
  samples_.clear();
  const uint32_t n = in.read<uint32_t>("recent motion count");
  constexpr uint64_t kSampleBytes = sizeof(double) * (1 + 16);  // the time, then the 4x4 pose
  if (uint64_t(n) * kSampleBytes > in.remaining()) in.fail("recent motion count " + std::to_string(n) + " exceeds the file");
  for (uint32_t i = 0; i < n; ++i) {
    const double timestamp = in.read<double>("recent motion time");
    const Pose T = readPose(in, "recent motion pose");
    if (!std::isfinite(timestamp) || (!samples_.empty() && !(timestamp > samples_.back().timestamp)))
      in.fail("recent motion times out of order");
    samples_.push_back({timestamp, T});
  }
}

}  // namespace vf::slam
