#pragma once
// Why a frame got no pose, or was not fused: one value per kind, for the run's reports.
#include <cstdint>

namespace vf {

// Why a frame's pose was not trusted (FrameResult::lost), one value per kind for the reports.
enum class LostReason : uint8_t {
  None,
  NoDepth,         // no valid depth in range (lens covered, sensor warming up, everything too far)
  NoPrediction,    // nothing fused yet to track against
  Diverged,        // the solve left the finite numbers
  FewInliers,      // too few of the measured pixels found a model partner
  HighResidual,    // the point-to-plane residual stayed above the limit
  TooFast,         // moved or turned more than a camera can between two frames
  Jump,            // the solution jumped away from the predicted motion
  Relocalising,    // lost before, and no candidate pose agreed with the model yet
  Probation,       // relocalised, but the pose did not hold for enough frames to be fused
  OutOfReach,      // a given pose lies beyond the volume's coordinate range
  Repeated,        // the same depth as the frame before (a recorder's duplicate): no pose of its own
  Collapse,        // matched far fewer pixels than the frames before it: a jump ICP did not follow
};
const char* lostReasonName(LostReason reason);

}  // namespace vf
