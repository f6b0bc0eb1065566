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

namespace vf::app {

// "tracked N of M frames, fused K", then the frames without a pose, counted by reason.
void printTrackingSummary(int frames, const std::vector<LostFrame>& lost, int frames_fused, int relocalisations);
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

}  // namespace vf::app
