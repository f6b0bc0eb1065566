#pragma once
// The ring corridor: a 2 m wide corridor closed round a 9 x 4 m block of rooms, 13 x 8 m
// outside, 2.5 m high, so that a walk along it comes back to where it started. Its walls are
// weakly textured paint; door recesses with white frames, pilasters, a radiator, ceiling lights
// and a few objects every few metres pin the camera along the corridor, except on a 5 m stretch
// of the north leg with nothing but plain walls, floor and ceiling (as real corridors have).
//
// Frame: metres, z up, floor at z = 0. The corridor is the space inside x in [0, 13], y in
// [0, 8] and outside the block x in [2, 11], y in [2, 6]. Walls are 0.25 m slabs (the block: a
// core and slabs round it) so that door recesses have depth.
#include "room_geometry.h"

namespace vf::synth {

struct CorridorLayout {
  static constexpr float kOuterX_m = 13.f, kOuterY_m = 8.f, kHeight_m = 2.5f;
  static constexpr float kBlockX0_m = 2.f, kBlockX1_m = 11.f, kBlockY0_m = 2.f, kBlockY1_m = 6.f;
  static constexpr float kWidth_m = 2.f;  // of the corridor
  // The featureless stretch: the north leg between these x (both walls plain, no ceiling light).
  static constexpr float kPlainX0_m = 3.8f, kPlainX1_m = 8.9f;
};

Room makeCorridor();

}  // namespace vf::synth
