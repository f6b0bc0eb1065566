#include "room_source.h"

#include <string>

#include "core/error.h"
#include "corridor_geometry.h"
#include "corridor_path.h"

namespace vf::synth {

Scene parseScene(const std::string& name) {
  if (name == "room") return Scene::kRoom;
  if (name == "corridor") return Scene::kCorridor;
  throw Error("scene '" + name + "': expected room or corridor");
}

std::string sceneName(Scene scene) { return scene == Scene::kCorridor ? "corridor" : "room"; }

RoomScanOptions scanDefaults(Scene scene) {
  RoomScanOptions o;
  o.scene = scene;
  if (scene == Scene::kCorridor) {
    o.frames = kCorridorDefaultFrames;
    o.sensor = kinectV1Sensor();
  }
  return o;
}

RoomScanSource::RoomScanSource(RoomScanOptions options)
    : options_(options), room_(options.scene == Scene::kCorridor ? makeCorridor() : makeRoom()) {
  const std::string what = "synthetic " + sceneName(options_.scene);
  if (options_.frames < 1) throw Error(what + ": frames must be at least 1, not " + std::to_string(options_.frames));
  if (options_.width < 16 || options_.height < 16 || options_.width > 8192 || options_.height > 8192)
    throw Error(what + ": image size " + std::to_string(options_.width) + "x" + std::to_string(options_.height) +
                " is outside 16..8192 pixels");
  if (options_.close_wall && options_.scene != Scene::kCorridor)
    throw Error("--close-wall: only the corridor has a plain wall to walk along (add --scene corridor)");
  if (options_.walk != 0 && options_.scene != Scene::kCorridor)
    throw Error("--walk: only the corridor has other walks (add --scene corridor)");
  std::vector<std::pair<std::string, FrameRange>> runs;
  for (const FrameRange& r : options_.gaps) runs.push_back({"--gap", r});
  for (const FrameRange& r : options_.blanks) runs.push_back({"--blank", r});
  for (const auto& [option, r] : runs) checkWithin(r, options_.frames, option);
  if (options_.close_wall) checkWithin(*options_.close_wall, options_.frames, "--close-wall");
  checkDisjoint(runs);

  intrinsics_ = kinectIntrinsics(options_.width, options_.height);
  walk_ = options_.scene == Scene::kCorridor ? corridorPath(options_.frames, options_.close_wall, options_.walk)
                                             : cameraPath(options_.frames);
  for (int i = 0; i < options_.frames; ++i) {
    bool left_out = false;
    for (const FrameRange& g : options_.gaps) left_out = left_out || g.contains(i);
    if (!left_out) written_.push_back(i);
  }
  if (written_.empty()) throw Error("--gap leaves no frame of the " + std::to_string(options_.frames) + " to write");
}

bool RoomScanSource::blank(int walk_index) const {
  for (const FrameRange& b : options_.blanks)
    if (b.contains(walk_index)) return true;
  return false;
}

Trajectory RoomScanSource::groundTruth() const {
  if (written_.size() == walk_.size()) return walk_;
  Trajectory t;
  for (int i : written_) t.push_back(walk_[size_t(i)]);
  return t;
}

Trajectory RoomScanSource::depthPoses() const {
  Trajectory t;
  for (int i : written_)
    if (!blank(i)) t.push_back(walk_[size_t(i)]);
  return t;
}

CleanView RoomScanSource::cleanView(int index) const {
  if (index < 0 || index >= size())
    throw Error("synthetic " + sceneName(options_.scene) + ": frame " + std::to_string(index) + " is outside 0.." +
                std::to_string(size() - 1));
  return renderClean(room_, intrinsics_, walk_[size_t(walkIndex(index))].T_world_cam);
}

RgbdFrame RoomScanSource::load(int index) const {
  const int walk_index = index >= 0 && index < size() ? walkIndex(index) : -1;
  RgbdFrame frame;
  if (walk_index >= 0 && blank(walk_index)) {  // a covered lens: nothing to render
    frame.depth.resize(options_.width, options_.height, 0.f);
    frame.color.resize(options_.width, options_.height, Rgb8{0, 0, 0, 255});
  } else {
    const CleanView view = cleanView(index);  // throws for an index out of range
    applySensor(view, options_.sensor, options_.seed, walk_index, frame);
  }
  frame.index = index;
  frame.timestamp = walk_[size_t(walk_index)].timestamp;
  frame.T_world_cam_given = walk_[size_t(walk_index)].T_world_cam;
  frame.name = sceneName(options_.scene) + "_" + std::to_string(walk_index);
  return frame;
}

namespace {

std::string sensorText(const SensorModel& s) {
  if (!s.noise) return "no noise";
  if (s.disparity_step_per_m > 0) return "Kinect v1 depth (disparity steps, per-pixel bias)";
  return "Kinect v1 noise";
}

}  // namespace

std::string RoomScanSource::description() const {
  const std::string scene =
      options_.scene == Scene::kCorridor ? "synthetic ring corridor 13 x 8 x 2.5 m" : "synthetic room 8 x 6 x 2.6 m";
  std::string text = scene + ", " + std::to_string(options_.frames) + " frames " + std::to_string(options_.width) + "x" +
                     std::to_string(options_.height) + ", seed " + std::to_string(options_.seed) + ", " +
                     sensorText(options_.sensor);
  for (const FrameRange& r : options_.gaps) text += ", gap " + toString(r);
  for (const FrameRange& r : options_.blanks) text += ", blank " + toString(r);
  if (options_.close_wall) text += ", close wall " + toString(*options_.close_wall);
  if (options_.walk != 0) text += ", walk " + std::to_string(options_.walk);
  return text;
}

}  // namespace vf::synth
