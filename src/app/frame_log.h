#pragma once
// `vdbfuse reconstruct --frame-log FILE.csv`: one row per frame of the first pass, with what the
// tracker knew of it. The run's summary says how many frames were lost; this says where the
// tracking grew weak before that: the share of pixels that matched the model falling, the
// residual rising, a direction of the view left free (a corridor along its length) and carried
// by the motion prior, a step that jumped or reversed. A spreadsheet or three lines of pandas
// read it; so does whoever tunes the tracker, who before had to add a print to the engine.
//
// Columns (README "Reading a run's frame log"):
//   frame, timestamp        the frame's index in the sequence and its time (s)
//   status                  tracked; map start (the run's first frame, or a new map's after a
//                           loss: placed, not matched, so the next seven columns are blank);
//                           given pose (--poses given: fused where the recording put it, the
//                           same seven blank); or why it got no pose (fusion/lost_reason.h)
//   fused                   1 when its depth went into the scene
//   matched                 share of the measured pixels that found a model partner
//   on_model                share of the measured pixels that land on the model's surface
//   rmse_mm                 point-to-plane residual of those partners
//   free_directions         directions of the pose the view left unconstrained (0-6)
//   weakest_share           the weakest direction's share of the constraint (blank: not measured)
//   jump_cm, jump_deg       how far the solution left the predicted pose
//   step_cm, step_deg       how far the camera moved and turned since the last tracked frame
//   step_change_cm          how far that step differs from the one before (both a frame long):
//                           millimetres for a real camera, centimetres where the solve followed
//                           an alias of the texture or slid
//   bricks                  bricks the fused depth reached
//   restarted               of those, bricks no frame of the tracking model's window had seen
//                           (the camera came back to them): cleared before this frame fused,
//                           so that their old, drifted copy does not pull the tracker
//   note                    the tracker's words for a frame it did not track (CSV-quoted), or
//                           for a tracked one whose pose came from a second solve, started at
//                           the motion prior or at the last second's median pace
//                           (IcpParams::second_start_at_prior, second_start_at_pace)
// A resumed run keeps the interrupted run's rows for the frames before its checkpoint.
#include <string>
#include <vector>

#include "core/frame.h"
#include "core/pose.h"
#include "fusion/pipeline.h"

namespace vf::app {

class FrameLog {
 public:
  // A resumed run: the rows of `csv_text` (an earlier csv()) for frames before `first_frame`,
  // and the steps from there on measured from `done`, the poses of the frames before it.
  void resume(const std::string& csv_text, int first_frame, const Trajectory& done);
  void add(const RgbdFrame& frame, const FrameResult& result);
  // The header line and one line per frame added.
  std::string csv() const;

 private:
  std::vector<std::string> rows_;
  Pose last_pose_ = Pose::Identity();  // the last tracked row's
  bool has_last_pose_ = false;
  int last_index_ = 0;
  Eigen::Vector3d last_step_ = Eigen::Vector3d::Zero();  // its step, where it had one a frame long
  bool has_last_step_ = false;
};

// A CSV field: as it is, or in double quotes (inner quotes doubled) where it holds a comma, a
// quote or a line break.
std::string csvField(const std::string& text);

}  // namespace vf::app
