#pragma once
// Where a lost camera is most likely to have got to (Tracker::placeNewMap, a new map's first
// pose), from its last second of well-tracked frames: it walked on at the median of their
// per-frame velocities, not at the last one, because the frames just before a loss are the least
// trustworthy. On the ring corridor (640x480 walk 0, its return to the start, in one build) the
// last ten frames before the tracker noticed had slid backwards along the corridor, accelerating
// to 3 m/s, and the last step carried on put the new map 1.6 m from the truth.
// The turn is the last step's, carried on, as before. The median turn carried on placed the
// corridor's new maps 23-70 deg off (gaps at frames 120 and 600, a covered lens at 300). Facing
// as it did placed them better than the last step's turn at 320x240 walk 0 (0.3 against 5 deg)
// and at the gap at frame 120 (11 against 30), worse at the covered lens (21 against 10), but
// the whole walks ended worse (no loop found across the maps: 320x240 walk 0 63.1 against 10.0
// cm ATE, the covered lens 86.6 against 21.2). Each is one draw of a chaotic run
// (scripts/tracking_judge.sh), so the old turn stays until a spread over seeds says otherwise.
#include <deque>

#include "core/byte_reader.h"
#include "core/pose.h"
#include "slam/keyframes.h"

namespace vf::slam {

class RecentMotion {
 public:
  explicit RecentMotion(double window_s = 1.0) : window_s_(window_s) {}

  // A well-tracked frame's pose. `follows`: the frame comes right after the last one added (no
  // frame lost between them); else the motion so far says nothing about the camera's now.
  void add(const Pose& T_world_cam, double timestamp, bool follows);
  bool empty() const { return samples_.empty(); }
  // The last pose added (the last one tracked well) and its time; identity and 0 before the first.
  Pose lastPose() const { return samples_.empty() ? Pose::Identity() : samples_.back().T_world_cam; }
  double lastTime() const { return samples_.empty() ? 0.0 : samples_.back().timestamp; }
  // The time between the last two poses added (NaN before there are two).
  double lastStepSeconds() const;

  // Where the camera is at `timestamp` had it walked on from the last pose at its median velocity
  // (each component of the per-frame camera-frame translation rates; at most max_speed_m_s) and
  // turned on as in its last step; the last pose when fewer than two frames are known.
  Pose extrapolate(double timestamp, double max_speed_m_s) const;

  void write(ByteWriter& w) const;
  void read(ByteReader& in);

 private:
  struct Sample {
    double timestamp;
    Pose T_world_cam;
  };
  double window_s_;
  std::deque<Sample> samples_;  // oldest first, consecutive frames within window_s_ of the last
};

}  // namespace vf::slam
