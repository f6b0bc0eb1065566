#pragma once
// Joining the maps of one run. A camera lost where its map could not find it again starts a new
// map (slam/tracker.h), placed where its recent pace would have taken it: a guess, metres off
// after a long gap. Before the pose graph is solved, each later map is moved whole to where the
// loops between it and the older maps agree it lies: started from the guess, the graph's robust
// loss would take those loops, metres off, for wrong ones. A map fewer than `min_loops` agreeing
// loops reach stays at the guess, and the loops into it are dropped: one look-alike place must
// not carry a whole map with it.
#include <vector>

#include "core/pose.h"
#include "slam/keyframes.h"
#include "slam/pose_graph.h"

namespace vf::slam {

struct JoinedMaps {
  std::vector<Pose> poses;       // per keyframe: where the graph starts from
  std::vector<bool> keep_loop;   // per loop: false for one into a map it does not join
  int maps = 1;
  int joined = 0;                // later maps moved onto the older ones by their loops
};

// poses: the keyframes' tracked poses; loops: detectLoops()'s, from the older keyframe to the newer.
JoinedMaps joinMaps(const KeyframeStore& keyframes, const std::vector<Pose>& poses,
                    const std::vector<PoseGraphEdge>& loops, int min_loops);

}  // namespace vf::slam
