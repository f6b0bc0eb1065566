#include "fusion/brick_chunks.h"

#include "fusion/brick_hash.h"
#include "fusion/raycast_kernels.h"

namespace vf {

void BrickChunks::clear() {
  index_.clear();
  chunks_.clear();
}

void BrickChunks::add(const Vec3i* coords, int first_slot, int count) {
  for (int i = 0; i < count; ++i) {
    // Arithmetic shifts floor negative coordinates too; a chunk coordinate fits a brick key.
    const Vec3i chunk{coords[i].x >> kChunkShift, coords[i].y >> kChunkShift, coords[i].z >> kChunkShift};
    const auto [it, fresh] = index_.try_emplace(brickKey(chunk), int(chunks_.size()));
    if (fresh) chunks_.push_back({chunk, {}});
    chunks_[size_t(it->second)].slots.push_back(first_slot + i);
  }
}

void BrickChunks::gatherVisible(const FrustumCull& cull, const Rigid3f& T_cam_world, float brick_edge_m,
                                std::vector<int>& slots) const {
  slots.clear();
  const float chunk_edge_m = kChunkBricks * brick_edge_m;
  // A little more than half the diagonal (0.866): float rounding must never cull a chunk that
  // holds a brick BrickRangeKernel would keep (the slack is 2.6 mm, rounding at 1 km 0.06 mm).
  const float radius = 0.88f * chunk_edge_m;
  for (const Chunk& c : chunks_) {
    const Vec3f corner0{c.coord.x * chunk_edge_m, c.coord.y * chunk_edge_m, c.coord.z * chunk_edge_m};
    const Vec3f center = T_cam_world * (corner0 + Vec3f{0.5f, 0.5f, 0.5f} * chunk_edge_m);
    if (!cull.outside(center, radius)) slots.insert(slots.end(), c.slots.begin(), c.slots.end());
  }
}

}  // namespace vf
