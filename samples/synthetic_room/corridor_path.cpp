#include "corridor_path.h"

#include <algorithm>
#include <cmath>
#include <cstdint>
#include <random>
#include <vector>

#include "corridor_geometry.h"
#include "room_path.h"

namespace vf::synth {
namespace {

using L = CorridorLayout;
constexpr double kDeg = M_PI / 180.0;
constexpr double kCornerRadius_m = 1.0;  // centred on the block's corners
constexpr double kStraight_m[4] = {L::kBlockX1_m - L::kBlockX0_m, L::kBlockY1_m - L::kBlockY0_m,
                                   L::kBlockX1_m - L::kBlockX0_m, L::kBlockY1_m - L::kBlockY0_m};
constexpr double kArc_m = 0.5 * M_PI * kCornerRadius_m;
constexpr double kWalkStart_m = 2.0;  // on the loop: x = 4 on the south leg
constexpr double kStraightSpeed_m_s = 1.0, kCornerSpeed_m_s = 0.8;
constexpr double kSpeedRamp_m = 0.75;  // the speed changes over this distance before and after a corner
constexpr double kTableStep_m = 0.001;
constexpr double kCloseRampMax_s = 1.5;

double smoothstep(double x) {
  x = std::clamp(x, 0.0, 1.0);
  return x * x * (3 - 2 * x);
}

double loopLength() { return 2 * (kStraight_m[0] + kStraight_m[1]) + 4 * kArc_m; }

// A point of the centre line at `s` metres from the south-west end of the south leg (any s:
// it wraps): position, heading (unwrapped: +2 pi per loop done) and how far into a corner
// (1 on the arc, easing to 0 kSpeedRamp_m before and after it).
struct CentrePoint {
  Eigen::Vector2d position;
  double heading = 0, corner = 0;
};
CentrePoint centreLine(double s) {
  const double length = loopLength();
  const double loops = std::floor(s / length);
  double r = s - loops * length;
  Eigen::Vector2d start(L::kBlockX0_m, L::kBlockY0_m - kCornerRadius_m);  // (2, 1)
  CentrePoint p;
  for (int leg = 0; leg < 4; ++leg) {
    const double heading = leg * 0.5 * M_PI;
    const Eigen::Vector2d dir(std::cos(heading), std::sin(heading)), left(-dir.y(), dir.x());
    const double straight = kStraight_m[leg];
    if (r < straight) {
      p.position = start + r * dir;
      p.heading = heading;
      const double to_corner = std::min(r, straight - r);  // corners at both ends
      p.corner = 1 - smoothstep(to_corner / kSpeedRamp_m);
      break;
    }
    r -= straight;
    const Eigen::Vector2d centre = start + straight * dir + kCornerRadius_m * left;
    if (r < kArc_m || leg == 3) {
      const double a = std::min(r, kArc_m) / kCornerRadius_m;
      p.position = centre - kCornerRadius_m * (std::cos(a) * left - std::sin(a) * dir);
      p.heading = heading + a;
      p.corner = 1;
      break;
    }
    r -= kArc_m;
    start = centre + kCornerRadius_m * dir;
  }
  p.heading += loops * 2 * M_PI;
  return p;
}

// Distance walked (from the walk's start) against time: the speed depends on the place, so the
// time of each millimetre is integrated once and looked up.
class WalkClock {
 public:
  explicit WalkClock(double duration_s) {
    times_.push_back(0);
    double s = 0;
    while (times_.back() <= duration_s + 1) {
      const double v0 = speed(s), v1 = speed(s + kTableStep_m);
      times_.push_back(times_.back() + kTableStep_m * 0.5 * (1 / v0 + 1 / v1));
      s += kTableStep_m;
    }
  }
  double distanceAt(double t) const {
    const auto it = std::upper_bound(times_.begin(), times_.end(), t);
    const size_t i = size_t(std::max<ptrdiff_t>(1, it - times_.begin())) - 1;
    if (i + 1 >= times_.size()) return double(i) * kTableStep_m;
    const double f = (t - times_[i]) / (times_[i + 1] - times_[i]);
    return (double(i) + f) * kTableStep_m;
  }
  static double speed(double walked_m) {
    return kStraightSpeed_m_s - (kStraightSpeed_m_s - kCornerSpeed_m_s) * centreLine(kWalkStart_m + walked_m).corner;
  }

 private:
  std::vector<double> times_;
};

// Longer looks at a side wall, sin^2 bumps: (start s, length s, yaw degrees, + = left).
struct SideLook {
  double start_s, length_s, yaw_deg;
};
constexpr int kSideLookCount = 3;

// How the camera is carried: the phases of its swing, nod, roll and weave, and where it looks
// at a side wall. Walk 0 is the walk this file's header describes; the others draw their
// phases and looks from the walk number, with the same amplitudes, so that they stay as far
// from the walls and turn about as fast (walks 1-5 under 90 deg/s, as walk 0; where a look
// meets both swings at their fastest, a walk can reach about 100).
struct CarryStyle {
  double swing_phase[2] = {0.5, 2.0}, pitch_phase = 1.0, roll_phase = 2.0, weave_phase[2] = {0.0, 1.0};
  SideLook looks[kSideLookCount] = {
      {3.0, 3.0, 40.0},    // the second door of the block, on the south leg
      {17.0, 3.0, -40.0},  // the plain outer wall of the north leg
      {35.5, 3.0, -35.0},  // the outer door of the south leg, on the second pass
  };
};

CarryStyle carryStyle(uint64_t walk) {
  CarryStyle style;
  if (walk == 0) return style;
  // Raw 64-bit draws scaled by hand: the standard distributions differ between libraries, and a
  // walk must be the same wherever it is generated.
  std::mt19937_64 draw(walk);
  auto uniform = [&](double a, double b) { return a + (b - a) * double(draw() >> 11) * 0x1.0p-53; };
  for (double& p : style.swing_phase) p = uniform(0, 2 * M_PI);
  style.pitch_phase = uniform(0, 2 * M_PI);
  style.roll_phase = uniform(0, 2 * M_PI);
  for (double& p : style.weave_phase) p = uniform(0, 2 * M_PI);
  // One look in each third of the default walk's 40 s, apart by at least a second.
  for (int i = 0; i < kSideLookCount; ++i) {
    const double side = draw() >> 63 ? 1.0 : -1.0;
    style.looks[i] = {uniform(2.0 + 13.0 * i, 11.0 + 13.0 * i), 3.0, side * uniform(30.0, 40.0)};
  }
  return style;
}

double sideLookYaw(const CarryStyle& style, double t) {
  double yaw = 0;
  for (const SideLook& l : style.looks) {
    const double x = (t - l.start_s) / l.length_s;
    if (x > 0 && x < 1) yaw += l.yaw_deg * kDeg * std::pow(std::sin(M_PI * x), 2);
  }
  return yaw;
}

Pose walkPose(const WalkClock& clock, const CarryStyle& style, double t, double close) {
  const double walked = clock.distanceAt(t);
  const double loop = kWalkStart_m + walked, length = loopLength();
  const CentrePoint c = centreLine(loop);
  const double phase = 2 * M_PI * loop / length;  // whole periods per loop: the weave comes back
  const double weave = 0.11 * std::sin(3 * phase + style.weave_phase[0]) +
                       0.04 * std::sin(7 * phase + style.weave_phase[1]);  // + = left
  const double lateral = (1 - close) * weave - close * (0.5 * L::kWidth_m - kCloseWallDistance_m);
  const Eigen::Vector2d left(-std::sin(c.heading), std::cos(c.heading));
  const Eigen::Vector2d xy = c.position + lateral * left;
  const double height = 1.45 + 0.03 * std::sin(5 * phase) + 0.006 * std::sin(2 * M_PI * walked / 0.7);

  const double swing = 12 * kDeg * std::sin(2 * M_PI * t / 8.0 + style.swing_phase[0]) +
                       5 * kDeg * std::sin(2 * M_PI * t / 3.3 + style.swing_phase[1]) + sideLookYaw(style, t);
  const double shake_yaw = 0.3 * kDeg * std::sin(7.0 * t + 1);
  const double yaw = c.heading + (1 - close) * swing - close * 0.5 * M_PI + shake_yaw;
  const double pitch = (1 - close) * (8 * kDeg + 3 * kDeg * std::sin(2 * M_PI * t / 5.3 + style.pitch_phase)) +
                       0.3 * kDeg * std::sin(9.0 * t);
  const double roll = (1 - close) * 2 * kDeg * std::sin(2 * M_PI * t / 6.1 + style.roll_phase) +
                      0.3 * kDeg * std::sin(8.0 * t + 2);
  return headingPose(Eigen::Vector3d(xy.x(), xy.y(), height), yaw, pitch, roll);
}

}  // namespace

double corridorLoopLength_m() { return loopLength(); }

double corridorLoopTime_s() {
  double t = 0;
  for (double s = 0; s < loopLength(); s += kTableStep_m)
    t += kTableStep_m * 0.5 * (1 / WalkClock::speed(s) + 1 / WalkClock::speed(s + kTableStep_m));
  return t;
}

double closeWallBlend(const FrameRange& r, int index) {
  if (!r.contains(index)) return 0;
  // Ramps over a third of the run, at most 1.5 s; frames FROM and FROM+COUNT-1 are at 0.
  const double ramp = std::min(kCloseRampMax_s * kFrameRateHz, std::max(1.0, (r.count - 1) / 3.0));
  const double in = (index - r.from) / ramp, out = (r.end() - 1 - index) / ramp;
  return smoothstep(std::min(in, out));
}

Trajectory corridorPath(int frames, const std::optional<FrameRange>& close_wall, uint64_t walk) {
  const WalkClock clock(double(frames) / kFrameRateHz);
  const CarryStyle style = carryStyle(walk);
  Trajectory path;
  path.reserve(size_t(std::max(frames, 0)));
  for (int i = 0; i < frames; ++i) {
    const double close = close_wall ? closeWallBlend(*close_wall, i) : 0.0;
    path.push_back({frameTimestamp(i), walkPose(clock, style, frameTimestamp(i) - kFirstTimestamp_s, close)});
  }
  return path;
}

}  // namespace vf::synth
