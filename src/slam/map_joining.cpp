#include "slam/map_joining.h"

namespace vf::slam {
namespace {

// Two placements of one map agree when they put its first keyframe within these of each other:
// loops of one return measure it to a few centimetres; a look-alike place is metres away.
constexpr double kAgreeM = 0.3;
constexpr double kAgreeDeg = 10.0;

bool samePlace(const Pose& a, const Pose& b) { return posesWithin(a, b, kAgreeM, kAgreeDeg); }

}  // namespace

JoinedMaps joinMaps(const KeyframeStore& keyframes, const std::vector<Pose>& poses,
                    const std::vector<PoseGraphEdge>& loops, int min_loops) {
  JoinedMaps out;
  out.poses = poses;
  out.keep_loop.assign(loops.size(), true);
  const int n = keyframes.size();
  if (n == 0) return out;
  out.maps = keyframes.maps();
  for (int map = 1; map < out.maps; ++map) {
    const int first = keyframes.firstOfMap(map);
    if (first == n) continue;  // a map that made no keyframe
    // Each loop from an older map into this one says where its first keyframe lies.
    std::vector<size_t> into;
    std::vector<Pose> placed_first;
    for (size_t k = 0; k < loops.size(); ++k) {
      const PoseGraphEdge& e = loops[k];
      if (keyframes[e.to].map != map || keyframes[e.from].map >= map) continue;
      const Pose to = out.poses[size_t(e.from)] * e.T_from_to;   // where the loop puts keyframe e.to
      into.push_back(k);
      placed_first.push_back(to * out.poses[size_t(e.to)].inverse() * out.poses[size_t(first)]);
    }
    // The placement most of them agree with.
    int best = -1, best_votes = 0;
    for (size_t a = 0; a < into.size(); ++a) {
      int votes = 0;
      for (size_t b = 0; b < into.size(); ++b) votes += samePlace(placed_first[a], placed_first[b]) ? 1 : 0;
      if (votes > best_votes) best = int(a), best_votes = votes;
    }
    const bool joins = best >= 0 && best_votes >= min_loops;
    for (size_t a = 0; a < into.size(); ++a)
      out.keep_loop[into[a]] = joins && samePlace(placed_first[size_t(best)], placed_first[a]);
    if (!joins) continue;
    // This map and the ones after it (placed after it by the guess) move together.
    const Pose move = placed_first[size_t(best)] * out.poses[size_t(first)].inverse();
    for (int i = first; i < n; ++i) out.poses[size_t(i)] = move * out.poses[size_t(i)];
    ++out.joined;
  }
  return out;
}

}  // namespace vf::slam
