#pragma once
#include <vector>

#include "core/volume_spec.h"
#include "fusion/volume.h"

namespace vf {

// Host-resident dense volume. Its arrays are reserved with lazily committed zero pages, so a
// 512^3 volume costs memory only for the bricks that fusion actually touches.
class DenseVolume {
 public:
  DenseVolume() = default;
  DenseVolume(const VolumeSpec& spec, bool with_classes);
  ~DenseVolume();
  DenseVolume(DenseVolume&& other) noexcept;
  DenseVolume& operator=(DenseVolume&& other) noexcept;
  DenseVolume(const DenseVolume&) = delete;
  DenseVolume& operator=(const DenseVolume&) = delete;

  const VolumeSpec& spec() const { return spec_; }
  const VolumeView& view() const { return view_; }
  bool hasClasses() const { return view_.class_vote != nullptr; }

  // Bricks that at least one frame touched (brick_stamp != 0), ascending.
  std::vector<int> observedBricks() const;
  // Bytes the arrays would take if every brick were touched.
  static size_t bytesPerVoxel(bool with_classes);
  // Forget everything (weights back to zero), keeping the reservation.
  void clear();

 private:
  void release();
  VolumeSpec spec_;
  VolumeView view_;
  struct Block {
    void* ptr = nullptr;
    size_t bytes = 0;
  };
  std::vector<Block> blocks_;
};

}  // namespace vf
