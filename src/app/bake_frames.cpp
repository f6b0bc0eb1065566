// Opening a scene's capture again at its fused poses, for the texture bake.
#include "app/bake_frames.h"

#include <tbb/parallel_for.h>

#include <algorithm>
#include <cmath>
#include <filesystem>
#include <memory>
#include <utility>
#include <nlohmann/json.hpp>

#include "app/open_source.h"
#include "core/error.h"
#include "io/labeled_source.h"
#include "io/trajectory_io.h"
#include "texture/texture_bake.h"

namespace vf::app {
namespace {

namespace fs = std::filesystem;

nlohmann::json sourceOptionsOf(const Scene& scene, const std::string& scene_path) {
  if (scene.meta.source_options_json.empty()) return nlohmann::json::object();
  try {
    return nlohmann::json::parse(scene.meta.source_options_json);
  } catch (const nlohmann::json::exception& e) {
    throw Error(scene_path + ": metadata 'vdbfuse_source_options' is not JSON: " + e.what());
  }
}

std::string jsonString(const nlohmann::json& j, const char* key) {
  return j.contains(key) && j[key].is_string() ? j[key].get<std::string>() : std::string();
}

Trajectory bakeTrajectory(const Scene& scene, const std::string& scene_path, const BakeFrameOptions& o,
                          std::string& from) {
  if (!o.trajectory.empty()) {
    from = o.trajectory;
    return readTumTrajectory(o.trajectory);
  }
  if (!scene.meta.trajectory_tum.empty()) {
    from = "the scene's metadata";
    return parseTumTrajectory(scene.meta.trajectory_tum, scene_path + " (metadata 'vdbfuse_trajectory_tum')");
  }
  const std::string beside = fs::path(scene_path).replace_extension(".txt").string();
  if (fs::exists(beside)) {
    from = beside;
    return readTumTrajectory(beside);
  }
  throw Error(scene_path + ": the scene records no trajectory and " + beside +
              " does not exist; give the poses it was fused at with --trajectory FILE");
}

// The image of labels in `classes`, grown by `dilation` pixels (a square).
Image<uint8_t> classMask(const LabelImage& labels, const std::set<int>& classes, int dilation) {
  const int w = labels.width(), h = labels.height();
  Image<uint8_t> seed(w, h, 0), out(w, h, 0);
  bool any = false;
  for (int y = 0; y < h; ++y)
    for (int x = 0; x < w; ++x)
      if (classes.count(int(labels(x, y)))) seed(x, y) = 1, any = true;
  if (!any) return out;
  // Separable max filter: rows, then columns.
  Image<uint8_t> rows(w, h, 0);
  for (int y = 0; y < h; ++y)
    for (int x = 0; x < w; ++x)
      if (seed(x, y))
        for (int d = std::max(0, x - dilation); d <= std::min(w - 1, x + dilation); ++d) rows(d, y) = 1;
  for (int y = 0; y < h; ++y)
    for (int x = 0; x < w; ++x)
      if (rows(x, y))
        for (int d = std::max(0, y - dilation); d <= std::min(h - 1, y + dilation); ++d) out(x, d) = 1;
  return out;
}

}  // namespace

BakeFrames loadBakeFrames(const Scene& scene, const std::string& scene_path, const std::set<int>& masked_classes,
                          const BakeFrameOptions& o) {
  if (o.max_frames < 1) throw Error("--bake-max-frames must be at least 1");
  const nlohmann::json recorded = sourceOptionsOf(scene, scene_path);
  BakeFrames out;
  // The capture: --frames, else the absolute path recorded at fusion time, else the source as given then.
  if (!o.frames.empty() && !fs::exists(o.frames)) throw Error("--frames " + o.frames + ": no such capture");
  out.capture = o.frames;
  if (out.capture.empty()) out.capture = jsonString(recorded, "path");
  if (out.capture.empty() || !fs::exists(out.capture)) out.capture = scene.meta.source;
  if (out.capture.empty() || !fs::exists(out.capture))
    throw Error(scene_path + ": the capture it was fused from (" +
                (scene.meta.source.empty() ? std::string("not recorded") : scene.meta.source) +
                ") is not there; give it with --frames CAPTURE");
  SourceOptions source_options;
  if (recorded.contains("format")) source_options.format = recorded["format"].get<std::string>();
  if (recorded.contains("intrinsics")) source_options.intrinsics = recorded["intrinsics"].get<std::string>();
  if (recorded.contains("depth_units_per_metre"))
    source_options.depth_units_per_metre = recorded["depth_units_per_metre"].get<float>();
  if (recorded.contains("min_confidence")) source_options.min_confidence = recorded["min_confidence"].get<int>();
  std::unique_ptr<FrameSource> source = openFrameSource(out.capture, source_options);
  // Classes never painted: those asked for and those fusion kept out as dynamic.
  std::set<int> masked = masked_classes;
  if (recorded.contains("dynamic_classes"))
    for (const auto& id : recorded["dynamic_classes"]) masked.insert(id.get<int>());
  if (!masked.empty()) {
    std::string labels = o.labels.empty() ? jsonString(recorded, "labels") : o.labels;
    if (labels.empty() || !fs::exists(labels))
      throw Error(scene_path + ": masking classes needs the label maps the scene was fused with" +
                  (labels.empty() ? std::string() : " (" + labels + " is not there)") + "; give them with --labels DIR");
    source = std::make_unique<LabeledFrameSource>(std::move(source), labels, scene.meta.classes, MissingLabels::Skip);
  }
  const Trajectory trajectory = bakeTrajectory(scene, scene_path, o, out.poses_from);
  std::vector<std::pair<double, Pose>> poses;
  for (const StampedPose& p : trajectory) poses.push_back({p.timestamp, p.T_world_cam});
  std::sort(poses.begin(), poses.end(), [](const auto& a, const auto& b) { return a.first < b.first; });

  out.frames_in_capture = source->size();
  const int stride = (source->size() + o.max_frames - 1) / o.max_frames;
  std::vector<int> indices;
  for (int i = 0; i < source->size(); i += std::max(1, stride)) indices.push_back(i);
  const size_t n = indices.size();
  std::vector<ColorImage> color(n);
  std::vector<DepthImage> depth(n);
  std::vector<Image<uint8_t>> mask(n);
  std::vector<Pose> pose(n);
  std::vector<char> usable(n, 0), unlabelled(n, 0);
  std::vector<double> sharpness(n, 0.0);
  tbb::parallel_for(size_t(0), n, [&](size_t k) {
    RgbdFrame frame = source->load(indices[k]);
    auto it = std::lower_bound(poses.begin(), poses.end(), frame.timestamp,
                               [](const auto& p, double t) { return p.first < t; });
    const Pose* match = nullptr;
    for (auto c : {it, it == poses.begin() ? it : it - 1})
      if (c != poses.end() && std::fabs(c->first - frame.timestamp) < 1e-3) match = &c->second;
    if (!match || frame.color.empty() || frame.depth.empty()) return;  // not fused (lost) or no colour
    if (!masked.empty() && frame.labels.empty()) {
      unlabelled[k] = 1;  // no mask: a person could be painted in from it
      return;
    }
    pose[k] = *match;
    if (!masked.empty()) mask[k] = classMask(frame.labels, masked, o.mask_dilation_px);
    sharpness[k] = imageSharpness(frame.color);
    color[k] = std::move(frame.color);
    depth[k] = std::move(frame.depth);
    usable[k] = 1;
  });
  std::vector<double> sharp;
  for (size_t k = 0; k < n; ++k) {
    out.frames_unlabelled += unlabelled[k];
    if (usable[k]) sharp.push_back(sharpness[k]);
  }
  if (sharp.empty())
    throw Error(out.capture + ": no frame of it has a pose in " + out.poses_from +
                " (wrong capture or trajectory? give them with --frames and --trajectory)");
  std::nth_element(sharp.begin(), sharp.begin() + long(sharp.size() / 2), sharp.end());
  const double median = std::max(sharp[sharp.size() / 2], 1e-9);
  const Intrinsics depth_k = source->depthIntrinsics();
  for (size_t k = 0; k < n; ++k) {
    if (!usable[k]) continue;
    out.frames_posed++;
    // Motion blur: well under the capture's typical sharpness, the frame is left out.
    if (sharpness[k] < 0.4 * median) {
      out.frames_blurred++;
      continue;
    }
    out.color.push_back(std::move(color[k]));
    out.depth.push_back(std::move(depth[k]));
    out.mask.push_back(std::move(mask[k]));
    BakeView view;
    view.T_cam_world = toRigid3f(pose[k].inverse());
    const Eigen::Vector3d c = pose[k].translation();
    view.centre_world = {float(c.x()), float(c.y()), float(c.z())};
    view.quality = float(std::min(1.0, sharpness[k] / median));
    out.views.push_back(view);
  }
  // Views into the images, now that the vectors no longer move.
  for (size_t k = 0; k < out.views.size(); ++k) {
    BakeView& v = out.views[k];
    const ColorImage& col = out.color[k];
    const DepthImage& dep = out.depth[k];
    v.depth_k = depth_k;
    if (dep.width() != depth_k.width || dep.height() != depth_k.height)
      throw Error(out.capture + ": a depth image of " + std::to_string(dep.width()) + "x" + std::to_string(dep.height()) +
                  " where the camera is " + std::to_string(depth_k.width) + "x" + std::to_string(depth_k.height));
    // The colour camera: the depth camera scaled to the colour size (pixel centres kept).
    const float sx = float(col.width()) / float(depth_k.width), sy = float(col.height()) / float(depth_k.height);
    v.color_k = {depth_k.fx * sx, depth_k.fy * sy, (depth_k.cx + 0.5f) * sx - 0.5f, (depth_k.cy + 0.5f) * sy - 0.5f,
                 col.width(), col.height()};
    v.color = col.view();
    v.depth = dep.view();
    if (!out.mask[k].empty()) v.mask = std::as_const(out.mask[k]).view();
  }
  return out;
}

}  // namespace vf::app
