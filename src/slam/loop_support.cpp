#include "slam/loop_support.h"

#include <cstdlib>

namespace vf::slam {
namespace {

// Where loop `e` puts keyframe `at` (the newer end or a neighbour of it), in the frame of the
// tracked poses around keyframe `anchor` (the older end of the loop being judged): the tracked
// motion from `anchor` to e's older end, e's measurement, then the tracked motion from e's newer
// end to `at`. Over a few keyframes the tracked motion is good to centimetres.
Pose placedBy(const PoseGraphEdge& e, int anchor, int at, const std::vector<Pose>& poses) {
  const Pose& older = poses[size_t(e.from)];
  const Pose& newer = poses[size_t(e.to)];
  return poses[size_t(anchor)].inverse() * older * e.T_from_to * newer.inverse() * poses[size_t(at)];
}

}  // namespace

std::vector<bool> corroboratedLoops(const KeyframeStore& keyframes, const std::vector<Pose>& poses,
                                    const std::vector<PoseGraphEdge>& loops, double agree_chi,
                                    const LoopSupportParams& params) {
  std::vector<bool> kept(loops.size(), true);
  auto oneMap = [&](const PoseGraphEdge& e) { return keyframes[e.from].map == keyframes[e.to].map; };
  for (size_t a = 0; a < loops.size(); ++a) {
    const PoseGraphEdge& e = loops[a];
    if (!oneMap(e) || edgeChi(e, poses) <= agree_chi) continue;
    const Pose placed = placedBy(e, e.from, e.to, poses);
    bool supported = false;
    for (size_t b = 0; b < loops.size() && !supported; ++b) {
      const PoseGraphEdge& f = loops[b];
      if (b == a || !oneMap(f) || std::abs(f.from - e.from) > params.neighbourhood ||
          std::abs(f.to - e.to) > params.neighbourhood)
        continue;
      supported = posesWithin(placed, placedBy(f, e.from, e.to, poses), params.agree_m, params.agree_deg);
    }
    kept[a] = supported;
  }
  return kept;
}

}  // namespace vf::slam
