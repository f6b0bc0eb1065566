#pragma once
// The walk round the ring corridor (corridor_geometry.h): a Kinect v1 carried at 1.45 m along
// the corridor's centre line, counter-clockwise (the block on the left), from x = 4 on the south
// leg, at 1.0 m/s on the straights and 0.8 m/s round the corners, weaving +-15 cm across the
// corridor. It looks along the corridor, swinging +-17 degrees, with three longer looks at a
// side wall. 1200 frames at 30 Hz walk 37.8 m, 1.17 times round the 32.3 m loop: it is back at
// its start after 34.6 s (frame 1037) and goes on 5 m along the south leg, over what it saw first.
//
// --walk N (N > 0): the same path round the loop at the same pace, the camera carried with other
// phases of its swing, nod, roll and weave, and its three looks at a side wall at other times
// (one in each third of the walk, 30-40 degrees, left or right): a walk that meets the hard views
// (a plain wall, a door at the end of the depth range) at other moments, to judge tracking on
// more than one walk. Walk 0 is the walk above.
//
// --close-wall FROM:COUNT: in those frames the camera turns right to face the outer wall square
// on and steps to 0.7 m from it, still walking (turning in and out over the first and last
// third, at most 1.5 s each); in between it sees only that wall, which leaves point-to-plane ICP
// three directions unconstrained (along the wall, up it, and rotation about its normal). Frames
// outside the run are the plain walk's.
#include <cstdint>
#include <optional>

#include "core/pose.h"
#include "frame_range.h"

namespace vf::synth {

constexpr int kCorridorDefaultFrames = 1200;
constexpr float kCloseWallDistance_m = 0.7f;
// A run on the north leg's plain stretch of the default walk: frames 555-614 see nothing but
// the wall (the camera slides from x = 7.8 to 6.3 m along it).
constexpr FrameRange kSuggestedCloseWall{510, 150};

double corridorLoopLength_m();  // the centre line, once round
// The time (s after the first frame) at which the walk is first back at its start.
double corridorLoopTime_s();

// The poses of frames 0..frames-1 of walk `walk`, 1/30 s apart from kFirstTimestamp_s (room_path.h).
Trajectory corridorPath(int frames, const std::optional<FrameRange>& close_wall = std::nullopt, uint64_t walk = 0);

// The close-up blend of frame `index`: 0 outside the run, rising to 1 (facing the wall at
// kCloseWallDistance_m) and back. The frames where it is 1 see only the wall.
double closeWallBlend(const FrameRange& close_wall, int index);

}  // namespace vf::synth
