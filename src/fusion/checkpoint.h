#pragma once
// Checkpoints of a running reconstruction: everything a stopped run needs to continue to the
// same volume and poses as a run that never stopped (bit for bit on the same backend).
//
// One binary file, written atomically (core/atomic_output.h) and closed by a checksum, holding:
//   - the run's settings (dataset, options: checked on resume, so that a checkpoint is never
//     continued with other input), the camera and the volume settings,
//   - the pipeline's frame state (counters, poses; fusion/pipeline.h PipelineState),
//   - the frames done, the trajectory and the lost-frame reports,
//   - every allocated brick: coordinate and voxels (TSDF + weight, colour, class vote).
// The tracking prediction itself is not stored: restoring raycasts it again from the saved pose.
#include <string>
#include <utility>
#include <vector>

#include "core/pose.h"
#include "fusion/lost_reason.h"

namespace vf {

class Pipeline;

// What must not change between a run and its resumption, as (name, value) pairs.
using RunSettings = std::vector<std::pair<std::string, std::string>>;

// A frame that got no pose, and why.
struct LostFrame {
  int index = 0;          // in the run's frame sequence
  std::string name;
  LostReason reason = LostReason::None;
  std::string why;        // the details, for the report
};

// The reconstruction's own part of a checkpoint.
struct RunProgress {
  RunSettings settings;
  int frames_done = 0;
  Trajectory trajectory;            // the poses of the frames done that have one
  std::vector<LostFrame> lost;      // the frames done that have none
  std::vector<uint8_t> session;     // the driver's own state (slam/: tracking, keyframes), opaque here
};

// Throws vf::Error naming `path` when it cannot be written (the old checkpoint then stays).
void writeCheckpoint(const std::string& path, Pipeline& pipeline, const RunProgress& progress);

// Verifies the file, checks that it belongs to a run with `settings` (naming the first setting
// that differs) and the pipeline's camera and volume, restores the pipeline (which must not have
// processed a frame yet) and returns the saved progress. Throws vf::Error naming `path` for a
// missing, truncated, corrupted or mismatching checkpoint.
RunProgress readCheckpoint(const std::string& path, Pipeline& pipeline, const RunSettings& settings);

// Only the settings a checkpoint was written with, its checksum verified (no pipeline needed).
RunSettings readCheckpointSettings(const std::string& path);

}  // namespace vf
