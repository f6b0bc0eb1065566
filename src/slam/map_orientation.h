#pragma once
// Turning a later map to face the way the older ones do, for the loop search. A map started where
// the camera was lost (slam/tracker.h) is placed where the camera's recent pace and turn would
// have taken it: its position within tens of centimetres, its rotation often ten or more degrees
// off (a walker turns while unseen, and tilts). Metres away, at the walk's return, that rotation
// puts the map's keyframes beyond the reach of every loop check (slam/loop_closure.h): the ring
// corridor cut at walk frame 600 placed its new map 13 degrees off (11 in heading, 7.5 in tilt),
// 1.6 m off at the return, and none of the 311 candidate pairs aligned. Rooms and corridors are
// built of few surface directions (floor, ceiling, walls at right angles), and the older maps show
// which: the smallest rotation that carries the later map's surface normals onto those
// directions is the turn its placement missed, up to the building's own symmetry (so only below
// kMaxMapTurnDeg). The loop search looks from there as well as from the placement; the loops
// decide where the map lies (slam/map_joining.h).
#include <optional>
#include <vector>

#include <Eigen/Core>

#include "core/pose.h"
#include "slam/keyframes.h"

namespace vf::slam {

// The directions many of the unit normals share: mean shift on the sphere with a window of
// window_deg, kept where at least min_share of the normals lie within it, 2 windows apart.
std::vector<Eigen::Vector3d> dominantDirections(const std::vector<Eigen::Vector3d>& normals, double window_deg = 10.0,
                                                double min_share = 0.05);

// The rotation, at most max_deg, that carries `normals` onto `directions` (each normal pulled to
// the nearest direction, in a window that narrows from max_deg): nullopt where the normals pin
// no rotation down (all on one direction and its opposite) or the rotation is larger.
std::optional<Eigen::Matrix3d> rotationOntoDirections(const std::vector<Eigen::Vector3d>& directions,
                                                      const std::vector<Eigen::Vector3d>& normals, double max_deg);

// A building's right angles leave a turn of 45 degrees ambiguous; keep well clear of it.
constexpr double kMaxMapTurnDeg = 40.0;

// The keyframes' poses with each later map turned about its first keyframe to face as the maps
// before it do, where the turn is at least min_turn_deg (below it, the estimate's own error: the
// ring corridor's maps placed within 2 degrees measured 1.7 to 2.7); the maps after it turn with
// it (their placement followed from it). `turned`: how many maps turned.
std::vector<Pose> orientLaterMaps(const KeyframeStore& keyframes, double min_turn_deg, int* turned = nullptr);

}  // namespace vf::slam
