#include "slam/map_orientation.h"

#include <Eigen/Geometry>
#include <Eigen/SVD>
#include <algorithm>
#include <cmath>

namespace vf::slam {
namespace {

double cosDeg(double deg) { return std::cos(deg * M_PI / 180.0); }
double angleDeg(const Eigen::Matrix3d& R) { return Eigen::AngleAxisd(R).angle() * 180.0 / M_PI; }

// Every stride-th normal of the keyframes of maps [first_map, last_map], in the world frame.
std::vector<Eigen::Vector3d> worldNormals(const KeyframeStore& keyframes, const std::vector<Pose>& poses, int first_map,
                                          int last_map, size_t stride) {
  std::vector<Eigen::Vector3d> out;
  for (int i = 0; i < keyframes.size(); ++i) {
    const Keyframe& k = keyframes[i];
    if (k.map < first_map || k.map > last_map) continue;
    const Eigen::Matrix3d R = poses[size_t(i)].linear();
    for (size_t p = 0; p < k.cloud.normals.size(); p += stride) {
      const Vec3f& n = k.cloud.normals[p];
      if (n.x == 0 && n.y == 0 && n.z == 0) continue;
      out.push_back(R * Eigen::Vector3d(n.x, n.y, n.z));
    }
  }
  return out;
}

// A keyframe cloud has about 19 000 normals; one in 16 of each keyframe's is plenty to find a
// building's few directions, and keeps the mean shift well under a second for a long walk.
constexpr size_t kNormalStride = 16;

}  // namespace

std::vector<Eigen::Vector3d> dominantDirections(const std::vector<Eigen::Vector3d>& normals, double window_deg,
                                                double min_share) {
  if (normals.empty()) return {};
  const double within = cosDeg(window_deg);
  struct Mode {
    Eigen::Vector3d direction;
    size_t support = 0;
  };
  std::vector<Mode> modes;
  constexpr size_t kSeeds = 200;
  const size_t step = std::max<size_t>(1, normals.size() / kSeeds);
  for (size_t s = 0; s < normals.size(); s += step) {
    Mode mode{normals[s], 0};
    for (int it = 0; it < 10; ++it) {
      Eigen::Vector3d sum = Eigen::Vector3d::Zero();
      mode.support = 0;
      for (const Eigen::Vector3d& n : normals)
        if (n.dot(mode.direction) >= within) sum += n, ++mode.support;
      if (sum.norm() < 1e-12) break;
      const Eigen::Vector3d next = sum.normalized();
      const bool settled = next.dot(mode.direction) > cosDeg(0.05);
      mode.direction = next;
      if (settled) break;
    }
    modes.push_back(mode);
  }
  std::stable_sort(modes.begin(), modes.end(), [](const Mode& a, const Mode& b) { return a.support > b.support; });
  std::vector<Eigen::Vector3d> out;
  for (const Mode& m : modes) {
    if (double(m.support) < min_share * double(normals.size())) break;
    bool apart = true;
    for (const Eigen::Vector3d& d : out) apart = apart && d.dot(m.direction) < cosDeg(2 * window_deg);
    if (apart) out.push_back(m.direction);
  }
  return out;
}

std::optional<Eigen::Matrix3d> rotationOntoDirections(const std::vector<Eigen::Vector3d>& directions,
                                                      const std::vector<Eigen::Vector3d>& normals, double max_deg) {
  if (directions.size() < 2 || normals.empty()) return std::nullopt;
  Eigen::Matrix3d R = Eigen::Matrix3d::Identity();
  for (const double window_deg : {max_deg, 20.0, 10.0, 6.0, 6.0}) {
    const double within = cosDeg(std::min(window_deg, max_deg));
    Eigen::Matrix3d B = Eigen::Matrix3d::Zero();  // sum of direction * normal^T over the pulled normals
    for (const Eigen::Vector3d& n : normals) {
      const Eigen::Vector3d turned = R * n;
      const Eigen::Vector3d* nearest = nullptr;
      double best = within;
      for (const Eigen::Vector3d& d : directions)
        if (d.dot(turned) >= best) best = d.dot(turned), nearest = &d;
      if (nearest) B += *nearest * n.transpose();
    }
    // Wahba's problem: the rotation maximising the sum of direction . (R normal).
    const Eigen::JacobiSVD<Eigen::Matrix3d> svd(B, Eigen::ComputeFullU | Eigen::ComputeFullV);
    const Eigen::Vector3d s = svd.singularValues();
    if (!(s(0) > 0) || s(1) < 0.05 * s(0)) return std::nullopt;  // one axis: the turn about it is unmeasured
    Eigen::Matrix3d D = Eigen::Matrix3d::Identity();
    D(2, 2) = (svd.matrixU() * svd.matrixV().transpose()).determinant() < 0 ? -1.0 : 1.0;
    R = svd.matrixU() * D * svd.matrixV().transpose();
  }
  if (angleDeg(R) > max_deg) return std::nullopt;
  return R;
}

std::vector<Pose> orientLaterMaps(const KeyframeStore& keyframes, double min_turn_deg, int* turned) {
  const int n = keyframes.size();
  std::vector<Pose> poses(static_cast<size_t>(n));
  for (int i = 0; i < n; ++i) poses[size_t(i)] = keyframes[i].T_world_cam;
  int count = 0;
  for (int map = 1; map < keyframes.maps(); ++map) {
    const int first = keyframes.firstOfMap(map);
    if (first == n) continue;  // a map that made no keyframe
    const std::vector<Eigen::Vector3d> directions =
        dominantDirections(worldNormals(keyframes, poses, 0, map - 1, kNormalStride));
    const auto R = rotationOntoDirections(directions, worldNormals(keyframes, poses, map, map, kNormalStride), kMaxMapTurnDeg);
    if (!R || angleDeg(*R) < min_turn_deg) continue;
    Pose turn = Pose::Identity();
    turn.linear() = *R;
    const Eigen::Vector3d about = poses[size_t(first)].translation();
    turn.translation() = about - *R * about;
    for (int i = first; i < n; ++i) poses[size_t(i)] = turn * poses[size_t(i)];
    ++count;
  }
  if (turned) *turned = count;
  return poses;
}

}  // namespace vf::slam
