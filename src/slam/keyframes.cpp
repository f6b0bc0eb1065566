#include "slam/keyframes.h"

#include <algorithm>
#include <cstring>
#include <cmath>
#include <numeric>

namespace vf::slam {

bool KeyframeStore::isNewView(const FrameCode& code, float novelty) const {
  if (code.empty()) return false;
  for (const Keyframe& k : keyframes_)
    if (FernEncoder::dissimilarity(code, k.code) <= novelty) return false;
  return true;
}

std::vector<int> KeyframeStore::nearest(const FrameCode& code, int k, int map) const {
  std::vector<std::pair<float, int>> scored;
  for (int i = 0; i < size(); ++i)
    if (map < 0 || keyframes_[size_t(i)].map == map) scored.push_back({FernEncoder::dissimilarity(code, keyframes_[size_t(i)].code), i});
  const size_t n = std::min(scored.size(), size_t(std::max(k, 0)));
  std::partial_sort(scored.begin(), scored.begin() + long(n), scored.end());
  std::vector<int> out;
  for (size_t i = 0; i < n; ++i) out.push_back(scored[i].second);
  return out;
}

void KeyframeStore::write(std::vector<uint8_t>& out) const {
  ByteWriter w(out);
  w.pod<uint32_t>(uint32_t(keyframes_.size()));
  for (const Keyframe& k : keyframes_) {
    w.pod<int32_t>(k.frame_index);
    w.pod<int32_t>(k.map);
    w.pose(k.T_world_cam);
    w.pod<uint32_t>(uint32_t(k.code.ferns.size()));
    w.bytes(k.code.ferns.data(), k.code.ferns.size());
    w.pod<uint32_t>(uint32_t(k.features.points_cam.size()));
    w.bytes(k.features.points_cam.data(), k.features.points_cam.size() * sizeof(Vec3f));
    w.bytes(k.features.descriptors.data(), k.features.descriptors.size());
    const KeyframeCloud& c = k.cloud;
    w.pod(c.camera);
    w.pod<uint32_t>(uint32_t(c.points.size()));
    w.bytes(c.points.data(), c.points.size() * sizeof(Vec3f));
    w.bytes(c.normals.data(), c.normals.size() * sizeof(Vec3f));
  }
}

Pose readPose(ByteReader& in, const std::string& what) {
  Pose T = Pose::Identity();
  for (int i = 0; i < 16; ++i) T.matrix().data()[i] = in.read<double>(what);
  if (!T.matrix().allFinite() || (T.linear() * T.linear().transpose() - Eigen::Matrix3d::Identity()).norm() > 1e-6 ||
      T.matrix().row(3) != Eigen::RowVector4d(0, 0, 0, 1))
    in.fail(what + " is not a finite rigid motion");
  return T;
}

void KeyframeStore::read(ByteReader& in) {
  keyframes_.clear();
  const uint32_t n = in.read<uint32_t>("keyframe count");
  if (n > in.remaining() / 8) in.fail("keyframe count " + std::to_string(n) + " exceeds the file");
  for (uint32_t i = 0; i < n; ++i) {
    Keyframe k;
    k.frame_index = in.read<int32_t>("keyframe frame index");
    k.map = in.read<int32_t>("keyframe map");
    if (k.map < 0 || (!keyframes_.empty() && k.map < keyframes_.back().map)) in.fail("keyframe map numbers out of order");
    k.T_world_cam = readPose(in, "keyframe pose");
    const uint32_t ferns = in.read<uint32_t>("keyframe code length");
    const uint8_t* code = in.take(ferns, "keyframe code");
    k.code.ferns.assign(code, code + ferns);
    const uint32_t points = in.read<uint32_t>("keyframe feature count");
    if (points > in.remaining() / (sizeof(Vec3f) + FrameFeatures::kDescriptorBytes))
      in.fail("keyframe feature count " + std::to_string(points) + " exceeds the file");
    k.features.points_cam.resize(points);
    std::memcpy(k.features.points_cam.data(), in.take(points * sizeof(Vec3f), "keyframe points"),
                points * sizeof(Vec3f));
    const uint8_t* d = in.take(uint64_t(points) * FrameFeatures::kDescriptorBytes, "keyframe descriptors");
    k.features.descriptors.assign(d, d + size_t(points) * FrameFeatures::kDescriptorBytes);
    KeyframeCloud& c = k.cloud;
    c.camera = in.read<Intrinsics>("keyframe cloud camera");
    const uint32_t cloud_points = in.read<uint32_t>("keyframe cloud size");
    if (cloud_points != uint32_t(std::max(c.camera.width, 0)) * uint32_t(std::max(c.camera.height, 0)) ||
        cloud_points > in.remaining() / (2 * sizeof(Vec3f)))
      in.fail("keyframe cloud of " + std::to_string(cloud_points) + " points does not fit its camera or the file");
    c.points.resize(cloud_points);
    c.normals.resize(cloud_points);
    std::memcpy(c.points.data(), in.take(cloud_points * sizeof(Vec3f), "keyframe cloud points"), cloud_points * sizeof(Vec3f));
    std::memcpy(c.normals.data(), in.take(cloud_points * sizeof(Vec3f), "keyframe cloud normals"), cloud_points * sizeof(Vec3f));
    keyframes_.push_back(std::move(k));
  }
}

}  // namespace vf::slam
