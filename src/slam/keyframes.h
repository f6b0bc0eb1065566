#pragma once
// The views worth remembering: frames tracked well whose appearance code differs from every
// stored one (InfiniTAM's harvesting rule), each with its pose, its code and its point features.
// Relocalisation looks a lost frame up here; loop detection pairs keyframes that saw one place.
#include <vector>

#include "core/byte_reader.h"
#include "core/pose.h"
#include "slam/frame_code.h"
#include "slam/frame_features.h"
#include "slam/keyframe_cloud.h"

namespace vf::slam {

struct Keyframe {
  int frame_index = 0;      // in the run's frame sequence
  // The map it was tracked in: a camera lost where the map could not find it again starts a new
  // one (slam/tracker.h), whose poses are only a guess relative to the older maps' until a loop
  // joins them (slam/global_optimisation.h).
  int map = 0;
  Pose T_world_cam = Pose::Identity();
  FrameCode code;
  FrameFeatures features;
  KeyframeCloud cloud;
};

class KeyframeStore {
 public:
  // True when no stored keyframe's code is within `novelty` (0..1) of this one.
  bool isNewView(const FrameCode& code, float novelty) const;
  void add(Keyframe keyframe) { keyframes_.push_back(std::move(keyframe)); }
  // Indices of the k stored keyframes whose codes are nearest, nearest first; of map `map` only
  // when it is 0 or more.
  std::vector<int> nearest(const FrameCode& code, int k, int map = -1) const;
  int size() const { return int(keyframes_.size()); }
  // How many maps the keyframes were tracked in (maps are numbered in order; 1 when empty), and
  // the index of the first keyframe of `map` (size() when it made none).
  int maps() const { return keyframes_.empty() ? 1 : keyframes_.back().map + 1; }
  int firstOfMap(int map) const {
    int i = 0;
    while (i < size() && keyframes_[size_t(i)].map != map) ++i;
    return i;
  }
  const Keyframe& operator[](int i) const { return keyframes_[size_t(i)]; }
  Keyframe& operator[](int i) { return keyframes_[size_t(i)]; }

  // For checkpoints: everything, as bytes, and back.
  void write(std::vector<uint8_t>& out) const;
  void read(ByteReader& in);

 private:
  std::vector<Keyframe> keyframes_;
};

// Appending plain values to a byte buffer (the counterpart of ByteReader).
class ByteWriter {
 public:
  explicit ByteWriter(std::vector<uint8_t>& out) : out_(out) {}
  template <class T>
  void pod(const T& v) {
    static_assert(std::is_trivially_copyable_v<T>);
    const auto* p = reinterpret_cast<const uint8_t*>(&v);
    out_.insert(out_.end(), p, p + sizeof v);
  }
  void bytes(const void* p, size_t n) {
    const auto* b = static_cast<const uint8_t*>(p);
    out_.insert(out_.end(), b, b + n);
  }
  void pose(const Pose& T) {
    for (int i = 0; i < 16; ++i) pod(T.matrix().data()[i]);
  }

 private:
  std::vector<uint8_t>& out_;
};

Pose readPose(ByteReader& in, const std::string& what);

}  // namespace vf::slam
