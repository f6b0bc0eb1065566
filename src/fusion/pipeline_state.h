#pragma once
// Checkpoints of a running Pipeline: everything processFrame() carries from one frame to the
// next, so that a run stopped after frame k and resumed from its checkpoint ends with the same
// volume and poses as a run that never stopped (bit for bit on the same backend).
//
// One binary file, written atomically (temp file in the same folder, fsync, rename) and closed by
// a checksum, holding:
//   - the volume settings and camera it belongs to (checked on restore),
//   - frame counters (processed, lost), the current pose, the pose of the tracking prediction,
//     the recorded poses used to express given poses in the first frame's world,
//   - the allocated-brick list, and for every observed brick its stamp and voxels (TSDF,
//     weight, colour, class vote),
//   - caller data (`annotations`: the app keeps its trajectory and run settings there).
// The tracking prediction itself is not stored: restore raycasts it again from the saved pose,
// exactly as the last processFrame() did.
#include <string>

namespace vf {

class Pipeline;

// Throws vf::Error naming `path` when it cannot be written.
void savePipelineState(const Pipeline& pipeline, const std::string& path, const std::string& annotations = {});

// Restores into a pipeline that has not processed a frame yet and was built with the same volume
// settings, camera and class setting. Throws vf::Error naming `path` (and what differs) for a
// missing, truncated, corrupted or mismatching checkpoint. `annotations`, when given, receives
// the caller data saved with it.
void restorePipelineState(Pipeline& pipeline, const std::string& path, std::string* annotations = nullptr);

// Only the caller data of a checkpoint (checksum verified), without a pipeline.
std::string readPipelineStateAnnotations(const std::string& path);

}  // namespace vf
