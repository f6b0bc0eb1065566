#include "app/frame_renders.h"

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <filesystem>

#include "io/image_io.h"

namespace vf::app {

ColorImage shadePrediction(const Prediction& prediction, const Pose& T_world_cam) {
  const int w = prediction.normal_world.width(), h = prediction.normal_world.height();
  ColorImage out(w, h, Rgb8{0, 0, 0, 255});
  const Eigen::Vector3d eye = T_world_cam.translation();
  for (int y = 0; y < h; ++y)
    for (int x = 0; x < w; ++x) {
      const Vec3f n = prediction.normal_world(x, y);
      if (n.x == 0.f && n.y == 0.f && n.z == 0.f) continue;
      const Vec3f v = prediction.vertex_world(x, y);
      const Vec3f to_eye = normalized(Vec3f{float(eye.x()) - v.x, float(eye.y()) - v.y, float(eye.z()) - v.z});
      const float lambert = std::max(0.f, dot(n, to_eye));
      const uint8_t g = uint8_t(std::lround(40.f + 215.f * lambert));
      out(x, y) = Rgb8{g, g, g, 255};
    }
  return out;
}

ColorImage composeRenderPanel(const RgbdFrame& frame, const Prediction& prediction, const Pose& T_world_cam) {
  const int w = prediction.normal_world.width(), h = prediction.normal_world.height();
  ColorImage panel(3 * w, h, Rgb8{0, 0, 0, 255});
  const ColorImage shaded = shadePrediction(prediction, T_world_cam);
  for (int y = 0; y < h; ++y)
    for (int x = 0; x < w; ++x) {
      // The input colour may be larger than the depth (iPhone): its pixel at the same place.
      if (!frame.color.empty())
        panel(x, y) = frame.color(x * frame.color.width() / w, y * frame.color.height() / h);
      if (!prediction.color.empty()) panel(w + x, y) = prediction.color(x, y);
      panel(2 * w + x, y) = shaded(x, y);
    }
  return panel;
}

RenderOutputs::RenderOutputs(std::string folder, std::string video)
    : folder_(std::move(folder)), video_path_(std::move(video)) {
  if (!folder_.empty()) std::filesystem::create_directories(folder_);
  // Whether a video can be written is known now, not after the first frame's work.
  if (!video_path_.empty()) requireVideoWritable(video_path_);
}

void RenderOutputs::add(int index, const RgbdFrame& frame, Pipeline& pipeline) {
  if (!enabled()) return;
  const Prediction prediction = pipeline.predict(true);
  const ColorImage panel = composeRenderPanel(frame, prediction, pipeline.pose());
  if (!folder_.empty()) {
    char name[32];
    std::snprintf(name, sizeof(name), "frame_%05d.png", index);
    writeColorPng((std::filesystem::path(folder_) / name).string(), panel);
  }
  if (!video_path_.empty()) {
    if (!video_) video_ = std::make_unique<VideoWriter>(video_path_, panel.width(), panel.height(), 30.0);
    video_->write(panel);
  }
}

void RenderOutputs::close() {
  if (video_) video_->close();
}

}  // namespace vf::app
