#pragma once
// The CPU raycast's index of allocated bricks by chunk (kChunkBricks^3 bricks), so that finding
// the bricks in view costs the chunks of the scene plus the bricks near the view, not a
// projection of every brick of the scene each frame (BrickRangeKernel culled 164 k bricks of the
// synthetic room one by one, 2 % of the run, growing with the scene).
//
// Exact: a chunk whose bounding sphere lies outside one of the frustum's planes holds no brick
// whose own (smaller, contained) sphere is inside it, so the bricks skipped are only bricks that
// BrickRangeKernel would have culled itself. The ray ranges, and so the raycast, do not change.
#include <cstdint>
#include <unordered_map>
#include <vector>

#include "core/math.h"

namespace vf {

struct FrustumCull;

class BrickChunks {
 public:
  static constexpr int kChunkShift = 2;  // 4 x 4 x 4 bricks: 18.75 cm at the default voxel
  static constexpr int kChunkBricks = 1 << kChunkShift;

  void clear();
  // Files slots first_slot .. first_slot + count - 1, whose brick coordinates are coords[0 .. count-1].
  void add(const Vec3i* coords, int first_slot, int count);
  // Replaces `slots` with every slot of the chunks that `cull` does not exclude, seen from
  // T_cam_world, for bricks of `brick_edge_m`.
  void gatherVisible(const FrustumCull& cull, const Rigid3f& T_cam_world, float brick_edge_m,
                     std::vector<int>& slots) const;
  size_t chunkCount() const { return chunks_.size(); }

 private:
  struct Chunk {
    Vec3i coord;
    std::vector<int> slots;
  };
  std::unordered_map<uint64_t, int> index_;  // chunk key -> chunks_ entry
  std::vector<Chunk> chunks_;
};

}  // namespace vf
