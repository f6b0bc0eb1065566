#include "slam/global_optimisation.h"

#include <algorithm>

#include "core/error.h"
#include "slam/map_joining.h"
#include "slam/map_orientation.h"

namespace vf::slam {

std::vector<Pose> optimiseTrajectory(KeyframeStore& keyframes, const std::vector<Pose>& poses,
                                     const std::vector<int>& anchors, const std::vector<PriorHeldStretch>& prior_held,
                                     const GlobalParams& params, GlobalReport* report) {
  if (anchors.size() != poses.size()) throw Error("optimiseTrajectory: one anchor per pose");
  GlobalReport r;
  r.keyframes = keyframes.size();
  r.maps = keyframes.maps();
  std::vector<Pose> out = poses;
  if (!params.loop_closure || keyframes.size() < 3) {
    if (report) *report = r;
    return out;
  }
  LoopStats stats;
  std::vector<PoseGraphEdge> edges = odometryEdges(keyframes, params.loops, prior_held);
  const size_t odometry = edges.size();
  std::vector<Pose> search_poses;
  if (r.maps > 1 && params.min_map_turn_deg > 0) {
    search_poses = orientLaterMaps(keyframes, params.min_map_turn_deg, &r.maps_turned);
    if (r.maps_turned == 0) search_poses.clear();
  }
  std::vector<PoseGraphEdge> loops = detectLoops(keyframes, params.loops, &stats, prior_held, search_poses);
  r.candidates = stats.candidates;
  r.loops_found = stats.verified;
  std::vector<Pose> before(size_t(keyframes.size()));
  for (int i = 0; i < keyframes.size(); ++i) before[size_t(i)] = keyframes[i].T_world_cam;
  const JoinedMaps joined = joinMaps(keyframes, before, loops, params.min_joining_loops);
  r.maps_joined = joined.joined;
  {
    const std::vector<bool> corroborated =
        corroboratedLoops(keyframes, joined.poses, loops, params.loops_agree_chi, params.support);
    std::vector<PoseGraphEdge> kept;
    for (size_t k = 0; k < loops.size(); ++k)
      if (joined.keep_loop[k] && corroborated[k]) kept.push_back(loops[k]);
    loops = std::move(kept);
  }
  edges.insert(edges.end(), loops.begin(), loops.end());
  if (loops.empty()) {
    if (report) *report = r;
    return out;
  }
  // Loops that agree with the odometry within their own noise (all but one or two) say it has not
  // drifted beyond what a loop can measure: nothing to correct. (Frame-to-frame alignments carry the sensor's
  // per-pixel depth bias, a degree between views of TUM fr1/xyz 90 frames apart, where the
  // tracker, against a model fused from many views, stays within 0.1 degree of the motion
  // capture.)
  int disagreeing = 0;
  for (const PoseGraphEdge& loop : loops) disagreeing += edgeChi(loop, before) > params.loops_agree_chi ? 1 : 0;
  // (Joined maps were moved: their loops agree with where they now start, not with the odometry.)
  if (r.maps_joined == 0 && disagreeing < std::min(params.min_disagreeing_loops, int(loops.size()))) {
    r.loops_accepted = int(loops.size());
    if (report) *report = r;
    return out;
  }
  const PoseGraphResult solved = optimisePoseGraph(joined.poses, edges, params.graph);
  for (size_t k = odometry; k < edges.size(); ++k) r.loops_accepted += solved.loop_kept[k] ? 1 : 0;
  if (r.loops_accepted == 0) {
    if (report) *report = r;
    return out;
  }
  std::vector<double> corrections;
  for (size_t k = 0; k < poses.size(); ++k) {
    const int a = anchors[k];
    if (a < 0 || a >= keyframes.size()) continue;
    out[k] = solved.poses[size_t(a)] * (before[size_t(a)].inverse() * poses[k]);
    const Eigen::Vector3d ahead(0, 0, 2.0);
    corrections.push_back(std::max((out[k].translation() - poses[k].translation()).norm(),
                                   (out[k] * ahead - poses[k] * ahead).norm()));
  }
  if (!corrections.empty()) {
    std::sort(corrections.begin(), corrections.end());
    r.largest_correction_m = corrections.back();
    r.median_correction_m = corrections[corrections.size() / 2];
  }
  r.moved_enough = r.largest_correction_m >= params.min_correction_m;
  if (report) *report = r;
  if (!r.moved_enough) return poses;
  for (int i = 0; i < keyframes.size(); ++i) keyframes[i].T_world_cam = solved.poses[size_t(i)];
  return out;
}

}  // namespace vf::slam
