#pragma once
// Finding where the camera came back: for each keyframe, older keyframes that look alike (their
// appearance codes, slam/frame_code.h) or that the odometry puts nearby are candidates; a
// candidate becomes a loop edge only when the two views' depth aligns (slam/keyframe_cloud.h)
// from a start their point features agree on, or from the odometry's guess (at 5 cm, and coarse
// to fine from 30 cm, as far as a long walk's odometry has drifted), with enough overlap,
// a small residual, and surfaces that pin the translation down (not a corridor seen along its
// length). The pose graph's robust loss and switching (slam/pose_graph.h) then deal with a wrong
// loop that looks right to every check.
#include <vector>

#include "slam/keyframes.h"
#include "slam/pose_graph.h"
#include "slam/prior_held.h"

namespace vf::slam {

struct LoopParams {
  int min_separation_frames = 90;        // keyframes nearer in the sequence are neighbours, not a loop
  int candidates_by_code = 3;            // per keyframe: the older ones with the nearest codes
  float max_code_dissimilarity = 0.6f;   // and only those at most this different
  int candidates_by_place = 3;           // per keyframe: the older ones the odometry puts nearest
  float max_candidate_distance_m = 1.0f;  // within this distance
  float max_candidate_angle_deg = 40.f;   // looking within this angle
  // A pair no start aligns (the odometry's guess, the point features') is tried again from the
  // guess slid along the newer camera's viewing and sideways axes, every slide_step_m up to
  // max_slide_m each way (loop_closure.cpp alignFromSlidStarts), when at least
  // min_held_frames_to_slide frames between the two were held by the motion prior: there the
  // tracker drifts along what it cannot see, a corridor's length, beyond the coarse alignment's
  // 30 cm reach (the ring corridor's walk 1 at 320x240 came back 57-62 cm down the corridor from
  // its start, and none of its 390 candidate pairs aligned). max_slide_m 0: no slid starts.
  double max_slide_m = 0.75;
  double slide_step_m = 0.25;
  int min_held_frames_to_slide = 30;
  float min_overlap = 0.3f;              // share of the newer view's points the older one explains
  float max_rmse_m = 0.015f;             // point-to-plane, over those points
  // And the two views' surfaces must pin the translation down in every direction: a corridor
  // seen along its length, or one wall, aligns as well anywhere along it, so it cannot say where
  // the camera came back. The weakest direction's share of the translation constraint
  // (CloudAlignment::weakestTranslationShare): the ring corridor's ten loops found without this
  // test were all wrong (by 0.5 to 4.4 m) and all below 0.011; 7-Scenes kitchen's 63 (500
  // frames) at least 0.034, TUM fr1/xyz's 0.072.
  double min_translation_share = 0.02;
  // The size of edge errors, for their information matrices (loop_closure.cpp edgeInformation):
  // A loop: two views' depth aligned to each other carries the sensor's per-pixel depth bias (a
  // degree or two between views far apart on a Kinect v1, a couple of centimetres at 1-2 m).
  double loop_sigma_m = 0.02;
  double odometry_sigma_m = 0.001;       // the tracker between two keyframes: this, plus
  double odometry_drift = 0.005;         // this share of the distance between them
  // Where the tracker's view left directions to the motion prior (slam/prior_held.h), its
  // odometry can slide along them by half the distance travelled. The ring corridor's slid 17-20
  // cm between keyframes 30-50 cm apart (frames 551-580 and 1147-1178) while each of those edges
  // claimed 2-3 cm along the corridor; the pose graph put the loops' correction elsewhere and
  // switched off two right loops (163-1178, 171-1187, 1 cm from the truth) that disagreed. Edges
  // between keyframes whose two clouds leave a direction this free are the ones that slid: of
  // the corridor's 126, the 13 with a weakest translation share below 0.0035 erred by 72 mm on
  // average (up to 203 mm), the others 2-11 mm (means by share band). So across held frames the
  // edge's variance along each translation direction grows by (prior_held_drift times the
  // distance the held frames travelled (at least the walk's median pace times their number: a
  // slide that turned back shrinks the tracked distance, not the doubt; 14 of 16 corridor runs
  // better, 2.3 laps 9.57 -> 9.14 cm, README), times min(1, free_translation_share / the direction's
  // share))^2: in full along a free direction, less along one its depth constrains
  // (loop_closure.cpp weakenFreeTranslation). Corridor ATE 14.0 -> 5.9 cm; a run without such
  // frames is unchanged.
  double prior_held_drift = 0.5;
  double free_translation_share = 0.003;
  // Between the last keyframe of one map and the first of the next (slam/tracker.h: a camera lost
  // where the map could not find it again), the edge is only where the camera's recent pace
  // would have taken it: standard deviations of a walk's worth of uncertainty, so that any loop
  // outweighs it, while a map no loop reaches still has a place.
  double new_map_sigma_m = 1.0;
  double new_map_sigma_deg = 30.0;
  void validate() const;
};

struct LoopStats {
  int candidates = 0;   // pairs checked
  int verified = 0;     // pairs whose depth aligned: loop edges
};

// The odometry edges between consecutive keyframes (their tracked poses, with the information of
// their depth's alignment at that pose, weaker across frames the motion prior held, and only a
// guess between two maps), then the loop edges found; node i is keyframe i.
std::vector<PoseGraphEdge> odometryEdges(const KeyframeStore& keyframes, const LoopParams& params,
                                         const std::vector<PriorHeldStretch>& prior_held = {});
// prior_held: where tracking leaned on the motion prior (slid starts are tried only across them).
// search_poses: one per keyframe, a second placement to look from besides the keyframes' own
// poses (its own candidates by place and guesses; slam/map_orientation.h turns later maps for
// it); empty: the keyframes' own poses only.
std::vector<PoseGraphEdge> detectLoops(const KeyframeStore& keyframes, const LoopParams& params, LoopStats* stats,
                                       const std::vector<PriorHeldStretch>& prior_held = {},
                                       const std::vector<Pose>& search_poses = {});

}  // namespace vf::slam
