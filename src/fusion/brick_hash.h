#pragma once
// The spatial hash from brick coordinates to slots of the brick pool (Niessner et al. 2013,
// "voxel hashing"; InfiniTAM and nvblox do the same), written once for both backends.
//
// Open addressing with linear probing over a power-of-two table of 64-bit keys. A key packs the
// three brick coordinates in 21 bits each, so the volume spans +-2^20 bricks per axis (+-49 km at
// 5.86 mm voxels): no box to choose. Entries are only ever added (a brick, once allocated, stays),
// so a lookup may stop at the first empty key. Inserts race through compare-and-swap on the key;
// the slot is assigned afterwards in a separate pass (AssignSlotsKernel), never by the thread
// that inserts, so no thread ever waits for another.
#include <cstdint>

#include "core/brick_volume.h"
#include "fusion/atomics.h"

namespace vf {

constexpr uint64_t kEmptyBrickKey = ~uint64_t(0);
constexpr int kBrickKeyBits = 21;
constexpr int kBrickCoordLimit = 1 << (kBrickKeyBits - 1);  // coordinates in [-limit, limit)
// Longest probe sequence an insert may walk before it reports the table as too full; the host
// then grows the table (load factor stays below 1/2, where linear probing averages ~2.5 probes).
constexpr int kMaxBrickProbes = 64;

VF_HD bool brickCoordInRange(Vec3i b) {
  return b.x >= -kBrickCoordLimit && b.x < kBrickCoordLimit && b.y >= -kBrickCoordLimit &&
         b.y < kBrickCoordLimit && b.z >= -kBrickCoordLimit && b.z < kBrickCoordLimit;
}
VF_HD uint64_t brickKey(Vec3i b) {
  const uint64_t mask = (uint64_t(1) << kBrickKeyBits) - 1;
  return (uint64_t(b.x + kBrickCoordLimit) & mask) << (2 * kBrickKeyBits) |
         (uint64_t(b.y + kBrickCoordLimit) & mask) << kBrickKeyBits | (uint64_t(b.z + kBrickCoordLimit) & mask);
}
VF_HD Vec3i brickFromKey(uint64_t key) {
  const uint64_t mask = (uint64_t(1) << kBrickKeyBits) - 1;
  return {int((key >> (2 * kBrickKeyBits)) & mask) - kBrickCoordLimit, int((key >> kBrickKeyBits) & mask) - kBrickCoordLimit,
          int(key & mask) - kBrickCoordLimit};
}
// murmur3's 64-bit finaliser: neighbouring bricks land far apart.
VF_HD uint32_t brickKeyHash(uint64_t k) {
  k ^= k >> 33;
  k *= 0xff51afd7ed558ccdull;
  k ^= k >> 33;
  k *= 0xc4ceb9fe1a85ec53ull;
  k ^= k >> 33;
  return uint32_t(k);
}

// One table entry: key, slot and the marking stamp share a 16-byte cell, so that a lookup costs
// one cache line, not one per array (the raycast's lookups were a sixth of its time).
struct BrickEntry {
  uint64_t key;     // kEmptyBrickKey where free
  int32_t slot;     // pool slot, -1 until assigned (or when the pool is full)
  uint32_t stamp;   // the last frame (1-based) whose marking listed this entry
};
static_assert(sizeof(BrickEntry) == 16, "hash entries are packed in 16 bytes");

// Plain view of the table (host or device pointers); passed by value into kernels.
struct BrickHashView {
  BrickEntry* entries = nullptr;
  uint32_t mask = 0;  // capacity - 1

  // Entry holding `key`, or -1.
  VF_HD int find(uint64_t key) const {
    uint32_t e = brickKeyHash(key) & mask;
    for (int probe = 0; probe < kMaxBrickProbes; ++probe, e = (e + 1) & mask) {
      const uint64_t k = entries[e].key;
      if (k == key) return int(e);
      if (k == kEmptyBrickKey) return -1;
    }
    return -1;
  }
  // Entry holding `key` after inserting it if absent; -1 when kMaxBrickProbes entries in a row
  // are taken (the table must grow). Safe against concurrent inserts of any keys.
  VF_HD int insert(uint64_t key) const {
    uint32_t e = brickKeyHash(key) & mask;
    for (int probe = 0; probe < kMaxBrickProbes; ++probe, e = (e + 1) & mask) {
      uint64_t k = loadRelaxed(&entries[e].key);
      if (k == kEmptyBrickKey) k = compareExchange(&entries[e].key, kEmptyBrickKey, key);
      if (k == kEmptyBrickKey || k == key) return int(e);
    }
    return -1;
  }
};

// Fills a table with free entries; runs over the capacity.
struct ClearBrickHashKernel {
  BrickHashView hash;
  VF_HD void operator()(int e) const { hash.entries[e] = BrickEntry{kEmptyBrickKey, -1, 0}; }
};

// Before a table is replaced: each allocated brick's last marking stamp, by slot, so that the
// new table still tells which bricks a recent frame saw (the tracking model's window,
// VolumeView::min_stamp). A stamp of the frame being marked is dropped: that frame's marking
// runs again from scratch and lists the brick again.
struct SaveSlotStampsKernel {
  BrickHashView hash;
  uint32_t* slot_stamp;    // per slot
  uint32_t marking_stamp;  // the frame being marked, if any
  VF_HD void operator()(int e) const {
    const BrickEntry entry = hash.entries[e];
    if (entry.key == kEmptyBrickKey || entry.slot < 0) return;
    slot_stamp[entry.slot] = entry.stamp == marking_stamp ? 0u : entry.stamp;
  }
};

// Re-inserts every allocated brick of the pool into a (larger, cleared) table, keeping its slot
// and its last marking stamp (SaveSlotStampsKernel, or a checkpoint's).
struct RehashBricksKernel {
  BrickHashView hash;
  const Vec3i* brick_coords;  // per slot
  int* overflow;              // set when an insert found no free entry
  const uint32_t* slot_stamp; // per slot

  VF_HD void operator()(int slot) const {
    const int e = hash.insert(brickKey(brick_coords[slot]));
    if (e < 0) {
      *overflow = 1;
      return;
    }
    hash.entries[e].slot = slot;
    hash.entries[e].stamp = slot_stamp[slot];
  }
};

}  // namespace vf
