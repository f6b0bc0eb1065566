#pragma once
// What `vdbfuse reconstruct` prints once the frames are fused: tracking, labels, timings, memory.
#include <string>
#include <vector>

#include "core/brick_volume.h"
#include "core/class_table.h"
#include "fusion/checkpoint.h"
#include "fusion/stage_timer.h"
#include "io/labeled_source.h"
#include "slam/global_optimisation.h"
#include "slam/prior_held.h"

namespace vf::app {

// "tracked N of M frames, fused K", then the frames without a pose, counted by reason.
void printTrackingSummary(int frames, const std::vector<LostFrame>& lost, int frames_fused, int relocalisations);
// The stretches of at least kPriorHeldReportFrames frames whose poses the motion prior carried in
// some direction (slam/prior_held.h): where the trajectory can have drifted unseen.
// Half a second at 30 Hz: shorter stretches drift by millimetres.
constexpr int kPriorHeldReportFrames = 15;
void printPriorHeld(const std::vector<slam::PriorHeldStretch>& stretches);
// The frames in those stretches.
int priorHeldFrames(const std::vector<slam::PriorHeldStretch>& stretches);
// "loop closure: N keyframes, K candidate pairs checked, F loops found, A hold; frames moved ...".
void printLoopClosure(const slam::GlobalReport& report, bool enabled);
void printLabelSummary(const LabelStats& stats, const ClassTable& classes, int frames);
// The wall time including decoding; with `stage_table`, first the per-stage medians and the
// frames/s they allow, and after it how many bricks a fused frame reached (median and largest;
// empty: not printed).
void printTimingTable(const StageTimer& timer, int frames, double wall_s, std::vector<int> bricks_per_frame,
                      bool stage_table);
// The volume's size and the process's real peak resident memory (getrusage), printed last so that
// the scene conversion and write are included.
void printMemory(int bricks, size_t volume_bytes);
// Peak resident memory of this process so far, MiB.
double peakResidentMiB();

// The figures of a finished run, for `--report-json`: what a workflow's summary table reads
// instead of parsing the printed lines.
struct RunFigures {
  int frames = 0, fused = 0, relocalisations = 0;
  int maps = 1;  // the tracker's maps: one more after each loss it could not recover (slam/tracker.h)
  int prior_held_frames = 0;    // priorHeldFrames
  int passes = 1;               // 2 where every frame was fused again (slam/reconstruction.h)
  int64_t bricks_restarted = 0; // slam::GlobalReport::bricks_restarted
  int resumed_after_frame = 0;  // frames a --resume found done; 0 for a run from the start
  std::vector<LostFrame> lost;
  double seconds = 0;  // this process's frame loop (the part after the checkpoint on --resume)
  int bricks = 0;
  size_t active_voxels = 0;
  std::string device;
};
// One JSON object: frames, tracked, fused, lost, lost_by_reason, relocalisations, maps, prior_held_frames,
// passes, bricks_restarted, resumed_after_frame, seconds, peak_mib (this process), bricks, active_voxels,
// device.
std::string runFiguresJson(const RunFigures& figures);

}  // namespace vf::app
