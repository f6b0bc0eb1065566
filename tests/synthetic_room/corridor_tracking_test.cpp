// Tracking along the synthetic corridor (issue 36): walking down a corridor whose far end lies
// beyond the depth range, the walls, floor and ceiling say little about the motion along it, so
// the tracker's motion prior carries that direction. Held at the prior outright, the direction
// ignored what the model still measured there and its error grew frame after frame (4.85 cm off
// the true motion after 25 frames, then a 4 cm jump once the view measured it again); pulled
// towards the prior no harder than the threshold of a weak direction, the model keeps it within
// millimetres (fusion/tracking.cpp solveIncrement). Full Kinect v1 resolution: at a quarter of the
// pixels the view constrains that direction differently. And round a corner facing one blank wall.
#include <gtest/gtest.h>

#include <cmath>

#include "fusion/pipeline.h"
#include "room_source.h"

namespace vf::synth {
namespace {

// How far the motion tracked since the first frame strayed from the true one, in cm, at worst
// over the frames: as a whole, and along the true motion alone (the walk's pace), with the walk
// index where each was.
struct Drift {
  double worst_cm = 0;
  int worst_frame = 0;
  double worst_pace_cm = 0;
  int worst_pace_frame = 0;
};

Drift driftOf(const RoomScanSource& source, const PipelineParams& params) {
  Pipeline pipeline(params, source.depthIntrinsics(), Device::Cpu);
  Pose first_estimate, first_truth;
  Drift drift;
  for (int i = 0; i < source.size(); ++i) {
    const RgbdFrame frame = source.load(i);
    const FrameResult result = pipeline.processFrame(frame);
    EXPECT_TRUE(result.tracked) << "frame " << source.walkIndex(i) << ": " << result.lost_reason;
    if (!result.tracked || !frame.T_world_cam_given) return {1e9, source.walkIndex(i), 1e9, source.walkIndex(i)};
    if (i == 0) {
      first_estimate = result.T_world_cam;
      first_truth = *frame.T_world_cam_given;
      continue;
    }
    // The motion since the first frame, estimated against true, in the first camera's frame.
    const Pose estimated = first_estimate.inverse() * result.T_world_cam;
    const Pose truth = first_truth.inverse() * *frame.T_world_cam_given;
    const Eigen::Vector3d error = estimated.translation() - truth.translation();
    const double error_cm = error.norm() * 100.0;
    if (error_cm > drift.worst_cm) drift.worst_cm = error_cm, drift.worst_frame = source.walkIndex(i);
    if (truth.translation().norm() > 1e-6) {
      const double pace_cm = std::abs(error.dot(truth.translation().normalized())) * 100.0;
      if (pace_cm > drift.worst_pace_cm) drift.worst_pace_cm = pace_cm, drift.worst_pace_frame = source.walkIndex(i);
    }
  }
  return drift;
}

// The corridor walk's frames first .. end-1, tracked from a fresh start at `first`.
RoomScanSource walkStretch(int first, int end) {
  RoomScanOptions options = scanDefaults(Scene::kCorridor);
  options.frames = end;
  options.gaps.push_back({0, first});
  return RoomScanSource(options);
}

TEST(CorridorTracking, AWalkAlongACorridorWithItsEndOutOfRangeKeepsItsPace) {
  RoomScanOptions options = scanDefaults(Scene::kCorridor);
  options.frames = 26;
  // 25 frames walk 81 cm. The weak directions pulled towards the prior: 1.31 cm behind or ahead
  // at worst (frame 5); held there outright: 9.3 cm (frame 20).
  const Drift drift = driftOf(RoomScanSource(options), PipelineParams{});
  EXPECT_LT(drift.worst_pace_cm, 2.0) << "worst at frame " << drift.worst_pace_frame;
  // A tilt about a line 2.6 m ahead (pitch with the camera centre rising 2.6 m per radian) is
  // nearly free too. Held at the camera centre's prior, the walk's vertical bob is followed only
  // in part: 2.76 cm low at frame 6, 0.31 at frame 15, 2.28 at frame 23, a cost this test
  // states rather than hides. Held at the measured points' mean instead (before 2026-12-06) this
  // start kept within 0.59 cm, but the whole corridor at 640x480 ended 5.9 cm (walk 0) and 77 cm
  // (walk 1) off, against 1.5 and 3.2 cm now (scripts/tracking_judge.sh).
  EXPECT_LT(drift.worst_cm, 3.5) << "worst at frame " << drift.worst_frame;
}

// Walking frames 150-250 round the first corner, the camera faces one blank wall for a second
// (frames 225-235): its Kinect noise tilts the model's normals every way, so that sliding along
// it looks 1.3-1.9 % constrained, more than the 1 % a free direction is allowed. Counted beyond
// the normals' own scatter (0.8-0.9 % there), it is free and follows the walk: 2.3 cm at worst;
// taken at face value the camera slides sideways by up to 9 cm a frame: 67 cm.
TEST(CorridorTracking, TurningACornerFacingOneBlankWallKeepsToTheWalk) {
  const RoomScanSource source = walkStretch(150, 251);
  const Drift drift = driftOf(source, PipelineParams{});
  EXPECT_LT(drift.worst_cm, 5.0) << "worst at walk frame " << drift.worst_frame;
  PipelineParams face_value;
  face_value.icp.degenerate_noise_floor = false;
  EXPECT_GT(driftOf(source, face_value).worst_cm, 10.0) << "the corner no longer needs the noise floor";
}

// Walking frames 290-335 down a leg past a radiator, the geometry again leaves the walk along
// the corridor free, and the photometric term measures it from the radiator's fins and little
// else. Started from the still guess, the coarsest level settles one fin period (4.8 cm) short of
// the true step of 3.2 cm, and the camera walks backwards at 1.6 cm a frame (96 cm in 25 frames
// of the whole walk). Started where the motion prior puts that direction
// (IcpParams::degenerate_start_at_prior), it keeps the pace: from a fresh start at frame 290,
// 1.17 cm along the walk and 2.17 cm in all at worst (0.71 in all with the points' mean held,
// before 2026-12-06), against 117 cm from the still start. The second solve from the prior
// (IcpParams::second_start_at_prior) finds the pace from the still start as well: 2.16 cm.
TEST(CorridorTracking, WalkingPastARadiatorsFinsKeepsThePace) {
  const RoomScanSource source = walkStretch(290, 336);
  const Drift drift = driftOf(source, PipelineParams{});
  EXPECT_LT(drift.worst_cm, 3.0) << "worst at walk frame " << drift.worst_frame;
  PipelineParams still_start;
  still_start.icp.degenerate_start_at_prior = false;
  still_start.icp.second_start_at_prior = false;
  EXPECT_GT(driftOf(source, still_start).worst_cm, 20.0) << "the still start no longer loses the fins";
  PipelineParams still_then_prior;
  still_then_prior.icp.degenerate_start_at_prior = false;
  EXPECT_LT(driftOf(source, still_then_prior).worst_cm, 3.0) << "the second solve from the prior no longer finds the pace";
}

}  // namespace
}  // namespace vf::synth
