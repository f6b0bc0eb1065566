#pragma once
// The per-frame picture of --renders / --video: input color | predicted color | L.N shaded
// model, side by side (the seed report's Figure 3).
#include "core/frame.h"
#include "fusion/pipeline.h"

namespace vf::app {

// Lambertian shading with a light at the camera: intensity = max(0, L.N), background black.
ColorImage shadePrediction(const Prediction& prediction, const Pose& T_world_cam);

ColorImage composeRenderPanel(const RgbdFrame& frame, const Prediction& prediction,
                              const Pose& T_world_cam);

}  // namespace vf::app
