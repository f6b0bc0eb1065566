#include "fusion/sparse_volume.h"

#include <sys/mman.h>
#include <sys/resource.h>
#include <unistd.h>

#include <algorithm>
#include <array>
#include <cstdio>
#include <cstring>
#include <optional>
#include <string>

#include "core/error.h"
#include "core/host_memory.h"
#include "fusion/brick_hash.h"
#include "fusion/cuda_api.h"
#include "fusion/integrate_kernels.h"
#include "fusion/parallel.h"

namespace vf {
namespace {

constexpr uint32_t kInitialHashCapacity = 1u << 16;
constexpr uint32_t kMaxHashCapacity = 1u << 30;
constexpr int kInitialGpuPoolBricks = 1 << 14;  // 64 MiB without classes
// The CPU pool starts as large (a few frames' bricks) and doubles in place as the scene grows.
constexpr int kInitialHostPoolBricks = 1 << 14;
// Slots are ints and voxel indices 64-bit: 2^26 bricks (34 G voxels) is far beyond any memory.
constexpr int kMaxPoolBricks = 1 << 26;
// Share of the memory available at start that the CPU pool may take (the scene conversion at
// the end needs room too), and of the address space left under a limit (ulimit -v).
constexpr double kHostMemoryShare = 0.6;

// Bytes of memory available to this process now: MemAvailable, else the physical memory; under
// an address-space limit (RLIMIT_AS) no more than the part of it not yet mapped, since every
// mapping counts against it whether or not it is ever touched.
uint64_t availableHostBytes() {
  uint64_t bytes = 0;
  if (const std::optional<HostMemory> m = readHostMemory()) bytes = m->available_bytes;
  else bytes = uint64_t(sysconf(_SC_PHYS_PAGES)) * uint64_t(sysconf(_SC_PAGESIZE));
  rlimit limit{};
  if (getrlimit(RLIMIT_AS, &limit) == 0 && limit.rlim_cur != RLIM_INFINITY) {
    uint64_t mapped_pages = 0;
    std::FILE* statm = std::fopen("/proc/self/statm", "r");
    if (statm) {
      unsigned long long pages = 0;
      if (std::fscanf(statm, "%llu", &pages) == 1) mapped_pages = pages;
      std::fclose(statm);
    }
    const uint64_t mapped = mapped_pages * uint64_t(sysconf(_SC_PAGESIZE));
    bytes = std::min<uint64_t>(bytes, uint64_t(limit.rlim_cur) > mapped ? uint64_t(limit.rlim_cur) - mapped : 0);
  }
  return bytes;
}

// Anonymous private mappings read as zero and commit a page only on first write; null when the
// address space is exhausted.
void* reserveHost(size_t bytes) {
  void* p = mmap(nullptr, bytes, PROT_READ | PROT_WRITE, MAP_PRIVATE | MAP_ANONYMOUS | MAP_NORESERVE, -1, 0);
  if (p == MAP_FAILED) return nullptr;
  // The raycast and the integration jump between bricks all over the pool: with 4 KiB pages
  // every brick cost a TLB miss, and the first write to each page a copy-on-write fault with a
  // TLB shootdown to the other cores (6 % of a room scan's time).
  adviseHugePages(p, bytes);
  return p;
}

// A host mapping grown to `new_bytes`: the kernel moves its pages (no copy) where it cannot grow
// in place, and the new part reads as zero. Null when the address space is exhausted.
void* growHost(void* p, size_t old_bytes, size_t new_bytes) {
  void* q = mremap(p, old_bytes, new_bytes, MREMAP_MAYMOVE);
  if (q == MAP_FAILED) return nullptr;
  adviseHugePages(q, new_bytes);
  return q;
}

}  // namespace

// The slot-major arrays of pool_capacity_ slots. CPU: mappings grown in place (mremap: nothing
// copied); CUDA: reallocated, with a copy of the slots in use, when they grow.
struct SparseVolume::Pool {
  struct Array {
    void* ptr = nullptr;
    size_t bytes_per_slot = 0;
  };
  Device device;
  size_t slots = 0;
  Array tsdf{nullptr, kBrickVoxels * sizeof(TsdfVoxel)};
  Array color{nullptr, kBrickVoxels * sizeof(Rgb8)};
  Array class_vote{nullptr, kBrickVoxels * sizeof(uint32_t)};
  Array coords{nullptr, sizeof(Vec3i)};

  Pool(Device d, bool with_classes) : device(d) {
    if (!with_classes) class_vote.bytes_per_slot = 0;
  }
  ~Pool() {
    for (Array* a : arrays()) release(*a);
  }
  std::array<Array*, 4> arrays() { return {&tsdf, &color, &class_vote, &coords}; }
  void release(Array& a) {
    if (!a.ptr) return;
    if (device == Device::Cuda) cuda::release(a.ptr);
    else munmap(a.ptr, a.bytes_per_slot * slots);
    a.ptr = nullptr;
  }
  // Arrays of `new_slots`, the first `used` slots kept; false (the old arrays kept) when memory
  // runs out.
  bool resize(size_t new_slots, size_t used) {
    if (device != Device::Cuda) return resizeHost(new_slots);
    std::array<void*, 4> fresh{};
    const std::array<Array*, 4> all = arrays();
    try {
      for (size_t i = 0; i < all.size(); ++i) {
        if (!all[i]->bytes_per_slot) continue;
        fresh[i] = cuda::allocate(all[i]->bytes_per_slot * new_slots);
        cuda::fillZero(fresh[i], all[i]->bytes_per_slot * new_slots);
        if (all[i]->ptr) cuda::copyOnDevice(fresh[i], all[i]->ptr, all[i]->bytes_per_slot * used);
      }
    } catch (const Error&) {  // out of device memory: keep the old arrays
      for (void* p : fresh)
        if (p) cuda::release(p);
      return false;
    }
    for (size_t i = 0; i < all.size(); ++i) {
      release(*all[i]);
      all[i]->ptr = fresh[i];
    }
    slots = new_slots;
    return true;
  }
  bool resizeHost(size_t new_slots) {
    const std::array<Array*, 4> all = arrays();
    std::array<void*, 4> grown{};
    size_t i = 0;
    for (; i < all.size(); ++i) {
      const Array& a = *all[i];
      if (!a.bytes_per_slot) continue;
      grown[i] = a.ptr ? growHost(a.ptr, a.bytes_per_slot * slots, a.bytes_per_slot * new_slots)
                       : reserveHost(a.bytes_per_slot * new_slots);
      if (!grown[i]) break;
    }
    if (i < all.size()) {  // out of address space: every array back to its old size
      for (size_t k = 0; k < i; ++k) {
        Array& a = *all[k];
        if (!grown[k]) continue;
        if (!a.ptr) munmap(grown[k], a.bytes_per_slot * new_slots);
        else a.ptr = mremap(grown[k], a.bytes_per_slot * new_slots, a.bytes_per_slot * slots, 0);  // shrinks in place
      }
      return false;
    }
    for (size_t k = 0; k < all.size(); ++k)
      if (all[k]->bytes_per_slot) all[k]->ptr = grown[k];
    slots = new_slots;
    return true;
  }
};

size_t SparseVolume::bytesPerBrick(bool with_classes) {
  return kBrickVoxels * (sizeof(TsdfVoxel) + sizeof(Rgb8) + (with_classes ? sizeof(uint32_t) : 0)) + sizeof(Vec3i);
}

size_t SparseVolume::initialDeviceBytes(bool with_classes) {
  return size_t(kInitialGpuPoolBricks) * bytesPerBrick(with_classes) +
         size_t(kInitialHashCapacity) * (sizeof(BrickEntry) + 2 * sizeof(int));
}

SparseVolume::SparseVolume(const VolumeSpec& spec, bool with_classes, Device device)
    : spec_(spec), with_classes_(with_classes), device_(device), pool_(std::make_unique<Pool>(device, with_classes)) {
  spec_.validate();
  spec_.truncation_m = spec_.truncationOrDefault();
  const size_t per_brick = bytesPerBrick(with_classes);
  if (spec_.max_bricks > 0) {
    pool_limit_ = int(std::min<size_t>(spec_.max_bricks, kMaxPoolBricks));
  } else if (device_ == Device::Cuda) {
    pool_limit_ = kMaxPoolBricks;  // device memory decides, when a growth fails
  } else {
    pool_limit_ = int(std::min<uint64_t>(uint64_t(double(availableHostBytes()) * kHostMemoryShare) / per_brick,
                                         kMaxPoolBricks));
  }
  if (pool_limit_ < 1)
    throw Error("volume: no memory is left for a single brick; free memory, or raise the address-space limit (ulimit -v)");
  const int initial =
      std::min(device_ == Device::Cuda ? kInitialGpuPoolBricks : kInitialHostPoolBricks, pool_limit_);
  if (!pool_->resize(size_t(initial), 0))
    throw Error("volume: cannot allocate " + std::to_string((size_t(initial) * per_brick) >> 20) +
                " MiB for the brick pool; free memory, or need less of it: raise VolumeSpec.voxel_size_m or lower "
                "MeasurementParams.max_depth_m");
  pool_capacity_ = initial;
  counters_.allocate(device_, kCounters);
  allocateHash(kInitialHashCapacity);
}

SparseVolume::~SparseVolume() = default;

size_t SparseVolume::bytesHeld() const {
  const size_t hash_bytes = size_t(hash_capacity_) * (sizeof(BrickEntry) + 2 * sizeof(int));
  return size_t(brick_count_) * bytesPerBrick(with_classes_) + hash_bytes;
}

void SparseVolume::refreshView() {
  view_.tsdf = static_cast<TsdfVoxel*>(pool_->tsdf.ptr);
  view_.color = static_cast<Rgb8*>(pool_->color.ptr);
  view_.class_vote = static_cast<uint32_t*>(pool_->class_vote.ptr);
  view_.brick_coords = static_cast<Vec3i*>(pool_->coords.ptr);
  view_.hash = BrickHashView{entries_.data(), hash_capacity_ - 1};
  view_.voxel_size_m = spec_.voxel_size_m;
  view_.truncation_m = spec_.truncation_m;
}

int SparseVolume::readCounter(Counter c) const {
  int v = 0;
  readCounters(c, 1, &v);
  return v;
}

void SparseVolume::setCounter(Counter c, int value) { setCounters(c, 1, &value); }

void SparseVolume::readCounters(Counter first, int n, int* values) const {
  if (device_ == Device::Cuda) cuda::copyToHost(values, counters_.data() + first, sizeof(int) * size_t(n));
  else std::copy(counters_.data() + first, counters_.data() + first + n, values);
}

void SparseVolume::setCounters(Counter first, int n, const int* values) {
  if (device_ == Device::Cuda) cuda::copyToDevice(counters_.data() + first, values, sizeof(int) * size_t(n));
  else std::copy(values, values + n, counters_.data() + first);
}

void SparseVolume::allocateHash(uint32_t capacity) {
  hash_capacity_ = capacity;
  entries_.allocate(device_, capacity);
  frame_entries_.allocate(device_, capacity);
  frame_slots_.allocate(device_, capacity);
  refreshView();
  parallelFor(device_, int(capacity), ClearBrickHashKernel{view_.hash});
}

// Re-inserts the allocated bricks into a table twice the size (or more, until they fit).
void SparseVolume::rehash(const uint32_t* slot_stamps) {
  // The bricks' last marking stamps, by slot, before the old table goes (tracking's window of
  // recent bricks reads them: Pipeline::raycastForTracking).
  Buffer<uint32_t> saved;
  if (!slot_stamps && brick_count_ > 0) {
    saved.allocate(device_, size_t(brick_count_));
    parallelFor(device_, int(hash_capacity_), SaveSlotStampsKernel{view_.hash, saved.data(), marking_stamp_});
    slot_stamps = saved.data();
  }
  uint32_t capacity = hash_capacity_;
  for (;;) {
    capacity *= 2;
    if (capacity > kMaxHashCapacity) throw Error("volume: the brick hash table cannot grow further");
    allocateHash(capacity);
    setCounter(kOverflow, 0);
    parallelFor(device_, brick_count_,
                RehashBricksKernel{view_.hash, view_.brick_coords, overflowFlag(), slot_stamps});
    if (readCounter(kOverflow) == 0) return;
  }
}

void SparseVolume::beginFrame(uint32_t stamp) {
  restarted_ = 0;
  startMarking(stamp);
}

void SparseVolume::startMarking(uint32_t stamp) {
  marking_stamp_ = stamp;
  // Load factor at most 0.4 before the frame leaves room for its new bricks (linear probing stays
  // short); a frame that still overflows makes growIfOverflowed() rehash and mark again.
  if (uint64_t(brick_count_) * 5 > uint64_t(hash_capacity_) * 2) rehash();
  static_assert(kFrameCount == 0 && kOverflow == 1 && kRestarted == 2 && kNewBricks == 3, "reset together");
  const int zeros[4] = {0, 0, 0, 0};
  setCounters(kFrameCount, 4, zeros);
  marked_ = -1;
  pool_full_ = false;
}

bool SparseVolume::growIfOverflowed() {
  static_assert(kFrameCount == 0 && kOverflow == 1 && kRestarted == 2, "read together");
  int marked_overflow_restarted[3];
  readCounters(kFrameCount, 3, marked_overflow_restarted);
  restarted_ += marked_overflow_restarted[2];
  if (marked_overflow_restarted[1] == 0) {
    marked_ = marked_overflow_restarted[0];  // assignSlots() needs no second wait for it
    return false;
  }
  // Forgets this frame's partial list and stamps: marking runs again from scratch. The bricks the
  // first run restarted stay counted (restarted_): their old stamps are gone with the old list.
  rehash();
  startMarking(marking_stamp_);
  return true;
}

bool SparseVolume::growPool(int needed) {
  if (needed <= pool_capacity_) return true;
  if (needed > pool_limit_) return false;
  size_t target = size_t(pool_capacity_);
  while (target < size_t(needed)) target *= 2;
  target = std::min(target, size_t(pool_limit_));
  if (!pool_->resize(target, size_t(brick_count_))) {
    pool_limit_ = pool_capacity_;  // memory is exhausted: this is as large as the pool gets
    refreshView();                 // a failed growth may still have moved some arrays (CPU)
    return false;
  }
  pool_capacity_ = int(target);
  refreshView();
  return true;
}

int SparseVolume::assignSlots() {
  const int touched = marked_ >= 0 ? marked_ : readCounter(kFrameCount);
  marked_ = -1;
  if (touched == 0) return 0;
  int* counters = counters_.data();
  parallelFor(device_, touched, CountNewBricksKernel{view_.hash, frameEntries(), counters + kNewBricks});
  const int fresh = readCounter(kNewBricks);  // (reset by beginFrame)
  if (fresh > 0 && !growPool(brick_count_ + fresh)) pool_full_ = true;
  static_assert(kPoolFull == kSlotCount + 1, "set together");
  const int slot_count_and_full[2] = {brick_count_, 0};
  setCounters(kSlotCount, 2, slot_count_and_full);
  parallelFor(device_, touched,
              AssignSlotsKernel{view_, frameEntries(), frameSlots(), counters + kSlotCount, pool_capacity_,
                                counters + kPoolFull});
  if (fresh > 0) {
    // Each of the `fresh` listed bricks without a slot takes one (the frame lists a brick once),
    // as far as the pool reaches: known without waiting for the GPU to say so. The CPU, where
    // reading is free, checks that the kernel agrees.
    const int before = brick_count_;
    brick_count_ = std::min(before + fresh, pool_capacity_);
    if (before + fresh > pool_capacity_) pool_full_ = true;
    if (device_ == Device::Cpu) {
      int slot_count_and_full_now[2];
      readCounters(kSlotCount, 2, slot_count_and_full_now);
      if (slot_count_and_full_now[0] != before + fresh || (slot_count_and_full_now[1] != 0) != pool_full_)
        throw Error("volume: slot assignment gave " + std::to_string(slot_count_and_full_now[0]) + " slots, expected " +
                    std::to_string(before + fresh) + " (a brick listed twice in one frame?)");
      chunks_.add(view_.brick_coords + before, before, brick_count_ - before);
    }
  }
  return touched;
}

int SparseVolume::bricksNearView(const FrustumCull& cull, const Rigid3f& T_cam_world, const int** slots) {
  if (device_ == Device::Cuda) {
    *slots = nullptr;
    return brick_count_;
  }
  chunks_.gatherVisible(cull, T_cam_world, kBrickSize * spec_.voxel_size_m, near_view_);
  *slots = near_view_.data();
  return int(near_view_.size());
}

BrickVolumeView SparseVolume::hostView() {
  if (device_ != Device::Cuda) {
    return {spec_.voxel_size_m, spec_.truncation_m, size_t(brick_count_), view_.brick_coords, view_.tsdf,
            view_.color, view_.class_vote};
  }
  HostBrickVolume& m = host_mirror_;
  m.voxel_size_m = spec_.voxel_size_m;
  m.truncation_m = spec_.truncation_m;
  m.with_classes = with_classes_;
  m.resize(size_t(brick_count_));
  const size_t voxels = size_t(brick_count_) * kBrickVoxels;
  cuda::copyToHost(m.coords.data(), view_.brick_coords, size_t(brick_count_) * sizeof(Vec3i));
  cuda::copyToHost(m.tsdf.data(), view_.tsdf, voxels * sizeof(TsdfVoxel));
  cuda::copyToHost(m.color.data(), view_.color, voxels * sizeof(Rgb8));
  if (with_classes_) cuda::copyToHost(m.class_vote.data(), view_.class_vote, voxels * sizeof(uint32_t));
  return m.view();
}

std::vector<uint32_t> SparseVolume::brickStamps() const {
  std::vector<uint32_t> stamps(size_t(brick_count_), 0u);
  if (brick_count_ == 0) return stamps;
  Buffer<uint32_t> by_slot(device_, size_t(brick_count_));
  // Every slot in use has its entry; a stamp equal to 0 drops nothing (no frame has stamp 0).
  parallelFor(device_, int(hash_capacity_), SaveSlotStampsKernel{view_.hash, by_slot.data(), 0u});
  by_slot.download(stamps.data(), stamps.size());
  return stamps;
}

void SparseVolume::restore(const HostBrickVolume& bricks, const std::vector<uint32_t>& stamps) {
  if (bricks.with_classes != with_classes_)
    throw Error(std::string("volume: the saved bricks were fused ") + (bricks.with_classes ? "with" : "without") +
                " classes");
  const int n = int(bricks.coords.size());
  if (stamps.size() != size_t(n))
    throw Error("volume: " + std::to_string(stamps.size()) + " brick stamps for " + std::to_string(n) + " bricks");
  if (n > pool_capacity_ && !growPool(n))
    throw Error("volume: " + std::to_string(n) + " saved bricks do not fit in memory (at most " +
                std::to_string(pool_limit_) + ")");
  for (const Vec3i& b : bricks.coords)
    if (!brickCoordInRange(b)) throw Error("volume: a saved brick lies outside the volume's range");
  const size_t voxels = size_t(n) * kBrickVoxels;
  auto put = [&](void* dst, const void* src, size_t bytes) {
    if (bytes == 0) return;  // no brick saved: the empty arrays' data() is null
    if (device_ == Device::Cuda) cuda::copyToDevice(dst, src, bytes);
    else std::memcpy(dst, src, bytes);
  };
  put(view_.brick_coords, bricks.coords.data(), size_t(n) * sizeof(Vec3i));
  put(view_.tsdf, bricks.tsdf.data(), voxels * sizeof(TsdfVoxel));
  put(view_.color, bricks.color.data(), voxels * sizeof(Rgb8));
  if (with_classes_) put(view_.class_vote, bricks.class_vote.data(), voxels * sizeof(uint32_t));
  brick_count_ = n;
  pool_full_ = false;
  chunks_.clear();
  if (device_ == Device::Cpu) chunks_.add(view_.brick_coords, 0, n);
  // A fresh table large enough for the load-factor rule, then every brick back in with its slot.
  uint32_t capacity = kInitialHashCapacity;
  while (uint64_t(n) * 5 > uint64_t(capacity) * 2) capacity *= 2;
  hash_capacity_ = capacity / 2;
  Buffer<uint32_t> slot_stamps(device_, std::max<size_t>(1, size_t(n)));
  if (n > 0) slot_stamps.upload(stamps.data(), size_t(n));
  rehash(slot_stamps.data());
}

}  // namespace vf
