#include "fusion/dense_volume.h"

#include <sys/mman.h>

#include <cstring>
#include <utility>

#include "core/error.h"

namespace vf {
namespace {

void* reserveZeroed(size_t bytes) {
  // Anonymous private mappings read as zero and commit a page only on first write.
  void* p = mmap(nullptr, bytes, PROT_READ | PROT_WRITE, MAP_PRIVATE | MAP_ANONYMOUS | MAP_NORESERVE,
                 -1, 0);
  if (p == MAP_FAILED)
    throw Error("volume: cannot reserve " + std::to_string(bytes >> 20) +
                " MiB of memory; lower --volume-size or raise --voxel-size-m");
  return p;
}

}  // namespace

DenseVolume::DenseVolume(const VolumeSpec& spec, bool with_classes) : spec_(spec) {
  spec_.validate();
  spec_.truncation_m = spec_.truncationOrDefault();
  view_.dims = spec_.dims;
  view_.bricks = {spec_.dims.x / kBrickSize, spec_.dims.y / kBrickSize, spec_.dims.z / kBrickSize};
  view_.voxel_size_m = spec_.voxel_size_m;
  view_.truncation_m = spec_.truncation_m;
  view_.origin_m = spec_.origin_m;
  const size_t n = spec_.voxelCount();
  auto take = [&](size_t bytes) {
    blocks_.push_back({reserveZeroed(bytes), bytes});
    return blocks_.back().ptr;
  };
  view_.tsdf = static_cast<TsdfVoxel*>(take(n * sizeof(TsdfVoxel)));
  view_.color = static_cast<Rgb8*>(take(n * sizeof(Rgb8)));
  if (with_classes) view_.class_vote = static_cast<uint32_t*>(take(n * sizeof(uint32_t)));
  view_.brick_stamp = static_cast<uint32_t*>(take(size_t(view_.brickCount()) * sizeof(uint32_t)));
}

DenseVolume::~DenseVolume() { release(); }

DenseVolume::DenseVolume(DenseVolume&& other) noexcept { *this = std::move(other); }

DenseVolume& DenseVolume::operator=(DenseVolume&& other) noexcept {
  if (this != &other) {
    release();
    spec_ = other.spec_;
    view_ = other.view_;
    blocks_ = std::move(other.blocks_);
    other.blocks_.clear();
    other.view_ = VolumeView{};
  }
  return *this;
}

void DenseVolume::release() {
  for (const Block& b : blocks_) munmap(b.ptr, b.bytes);
  blocks_.clear();
}

std::vector<int> DenseVolume::observedBricks() const {
  std::vector<int> out;
  const int n = view_.brickCount();
  for (int b = 0; b < n; ++b)
    if (view_.brick_stamp[b] != 0) out.push_back(b);
  return out;
}

size_t DenseVolume::bytesPerVoxel(bool with_classes) {
  return sizeof(TsdfVoxel) + sizeof(Rgb8) + (with_classes ? sizeof(uint32_t) : 0);
}

void DenseVolume::clear() {
  // Re-map instead of memset so cleared pages stop counting as resident.
  for (Block& b : blocks_) {
    munmap(b.ptr, b.bytes);
    void* p = reserveZeroed(b.bytes);
    if (b.ptr == view_.tsdf) view_.tsdf = static_cast<TsdfVoxel*>(p);
    else if (b.ptr == view_.color) view_.color = static_cast<Rgb8*>(p);
    else if (b.ptr == view_.class_vote) view_.class_vote = static_cast<uint32_t*>(p);
    else view_.brick_stamp = static_cast<uint32_t*>(p);
    b.ptr = p;
  }
}

}  // namespace vf
