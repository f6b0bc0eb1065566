#pragma once
// The per-frame picture of --renders / --video: input color | predicted color | L.N shaded
// model, side by side (the seed report's Figure 3).
#include <memory>
#include <string>

#include "core/frame.h"
#include "fusion/pipeline.h"
#include "io/video_writer.h"

namespace vf::app {

// Lambertian shading with a light at the camera: intensity = max(0, L.N), background black.
ColorImage shadePrediction(const Prediction& prediction, const Pose& T_world_cam);

ColorImage composeRenderPanel(const RgbdFrame& frame, const Prediction& prediction,
                              const Pose& T_world_cam);

// The panels of a run: a PNG per frame in `folder` (frame_NNNNN.png) and/or an MP4 `video`;
// either may be empty. add() renders the model from the pipeline's current pose.
class RenderOutputs {
 public:
  RenderOutputs(std::string folder, std::string video);
  bool enabled() const { return !folder_.empty() || !video_path_.empty(); }
  void add(int index, const RgbdFrame& frame, Pipeline& pipeline);
  void close();  // finishes the video (renamed into place)

 private:
  std::string folder_, video_path_;
  std::unique_ptr<VideoWriter> video_;
};

}  // namespace vf::app
