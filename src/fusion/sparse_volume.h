#pragma once
// Owner of the sparse volume's memory on one backend: the brick pool (voxel arrays and brick
// coordinates, by slot), the spatial hash (fusion/brick_hash.h) and the per-frame brick lists,
// and the policy by which they grow. Kernels see it through view().
//
// Pool memory: on the CPU mappings that double in place (mremap: nothing is copied as the scene
// grows) and commit a page only when a brick first writes it, up to a share of the memory
// available at start and of the address space an RLIMIT_AS leaves (reserving that share up front
// failed a 3-frame job under ulimit -v); on the GPU an allocation that doubles, with a
// device-side copy, when a frame needs more bricks than it has. When memory runs
// out the pool stays full: bricks beyond it are not allocated and processFrame says so, so the
// caller can stop and save what was fused (never a silent stop, never a crash).
#include <cstddef>
#include <cstdint>
#include <memory>
#include <vector>

#include "core/brick_volume.h"
#include "core/volume_spec.h"
#include "fusion/brick_chunks.h"
#include "fusion/buffer.h"
#include "fusion/device.h"
#include "fusion/volume.h"

namespace vf {

class SparseVolume {
 public:
  SparseVolume(const VolumeSpec& spec, bool with_classes, Device device);
  ~SparseVolume();
  SparseVolume(const SparseVolume&) = delete;
  SparseVolume& operator=(const SparseVolume&) = delete;

  const VolumeView& view() const { return view_; }
  Device device() const { return device_; }
  bool hasClasses() const { return with_classes_; }
  int brickCount() const { return brick_count_; }      // slots in use
  int poolCapacity() const { return pool_capacity_; }  // slots available now
  int poolLimit() const { return pool_limit_; }        // slots memory allows at most
  static size_t bytesPerBrick(bool with_classes);
  // Device bytes a CUDA volume allocates when it is created (the first pool and hash table).
  static size_t initialDeviceBytes(bool with_classes);
  // Memory held for the volume now (pool committed so far, hash, lists).
  size_t bytesHeld() const;

  // Allocation, one frame at a time (Pipeline::integrate):
  // 1. beginFrame(stamp): the hash has room for the frame (it grows between frames) and the list
  //    is empty; `stamp` is the frame's marking stamp (MarkBricksKernel::stamp).
  void beginFrame(uint32_t stamp);
  // The per-frame lists and counters the marking kernel writes.
  int* frameEntries() const { return frame_entries_.data(); }
  int* frameSlots() const { return frame_slots_.data(); }
  int* frameCount() const { return counters_.data() + kFrameCount; }
  int* overflowFlag() const { return counters_.data() + kOverflow; }
  int* restartedCount() const { return counters_.data() + kRestarted; }  // MarkBricksKernel::restarted
  // 2. after marking: true when the hash overflowed; it has then grown, and marking must run again.
  bool growIfOverflowed();
  // After marking (growIfOverflowed() false): the bricks the frame's marking restarted, those of
  // a marking that overflowed and ran again included.
  int frameRestarted() const { return restarted_; }
  // 3. gives the frame's new bricks slots (growing the pool where it can); returns the number of
  //    bricks the frame touched. poolFull() tells whether some of them found no slot this frame.
  int assignSlots();
  bool poolFull() const { return pool_full_; }

  // The bricks a raycast from T_cam_world must project (BrickRangeKernel::slots), returning their
  // count: on the CPU the bricks of the chunks (fusion/brick_chunks.h) that `cull` does not
  // exclude, listed in *slots; on CUDA every slot (*slots = null), where one thread per brick
  // costs less than a host round trip each frame.
  int bricksNearView(const FrustumCull& cull, const Rigid3f& T_cam_world, const int** slots);

  // A host view of every allocated brick. CPU: the live pool; CUDA: a copy refreshed by each call.
  BrickVolumeView hostView();
  // Each allocated brick's last marking stamp (the frame whose marking last listed it), by slot:
  // what decides whether tracking still sees it (VolumeView::min_stamp).
  std::vector<uint32_t> brickStamps() const;
  // Replaces the content with `bricks` (slots 0..n-1 in their order) and their stamps
  // (brickStamps(), one per brick), as a checkpoint saved them.
  void restore(const HostBrickVolume& bricks, const std::vector<uint32_t>& stamps);

 private:
  // Device-side counters. Each host read of one is a wait for the GPU, so those read or reset
  // together lie together: a frame resets the first four at once, reads the first three at once.
  enum Counter { kFrameCount = 0, kOverflow, kRestarted, kNewBricks, kSlotCount, kPoolFull, kCounters };
  struct Pool;
  void allocateHash(uint32_t capacity);
  // beginFrame() but for the count of restarted bricks (a marking run again keeps it).
  void startMarking(uint32_t stamp);
  // Into a table twice the size (or more, until the bricks fit); each brick keeps its last
  // marking stamp, or takes it from `slot_stamps` (device memory, one per slot) when given.
  void rehash(const uint32_t* slot_stamps = nullptr);
  void refreshView();
  bool growPool(int needed);
  int readCounter(Counter c) const;
  void setCounter(Counter c, int value);
  // Counters first .. first + n - 1 in one copy (on the GPU: one wait, one upload).
  void readCounters(Counter first, int n, int* values) const;
  void setCounters(Counter first, int n, const int* values);

  VolumeSpec spec_;
  bool with_classes_;
  Device device_;
  std::unique_ptr<Pool> pool_;
  int pool_capacity_ = 0;
  int pool_limit_ = 0;
  int brick_count_ = 0;
  bool pool_full_ = false;
  uint32_t hash_capacity_ = 0;
  uint32_t marking_stamp_ = 0;  // the frame beginFrame() was last given
  int marked_ = -1;             // the frame's marked bricks, read with the overflow flag; -1: not yet read
  int restarted_ = 0;           // the frame's restarted bricks (frameRestarted())
  Buffer<BrickEntry> entries_;
  Buffer<int> frame_entries_;
  Buffer<int> frame_slots_;
  Buffer<int> counters_;
  VolumeView view_;
  HostBrickVolume host_mirror_;  // CUDA only: what hostView() last downloaded
  BrickChunks chunks_;           // CPU only: every slot by chunk
  std::vector<int> near_view_;   // CPU only: the last bricksNearView list
};

}  // namespace vf
