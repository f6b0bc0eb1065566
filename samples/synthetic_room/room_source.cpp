#include "room_source.h"

#include <string>

#include "core/error.h"

namespace vf::synth {

RoomScanSource::RoomScanSource(RoomScanOptions options) : options_(options), room_(makeRoom()) {
  if (options_.frames < 1) throw Error("synthetic room: frames must be at least 1, not " + std::to_string(options_.frames));
  if (options_.width < 16 || options_.height < 16 || options_.width > 8192 || options_.height > 8192)
    throw Error("synthetic room: image size " + std::to_string(options_.width) + "x" + std::to_string(options_.height) +
                " is outside 16..8192 pixels");
  intrinsics_ = kinectIntrinsics(options_.width, options_.height);
  path_ = cameraPath(options_.frames);
}

CleanView RoomScanSource::cleanView(int index) const {
  if (index < 0 || index >= options_.frames)
    throw Error("synthetic room: frame " + std::to_string(index) + " is outside 0.." + std::to_string(options_.frames - 1));
  return renderClean(room_, intrinsics_, path_[size_t(index)].T_world_cam);
}

RgbdFrame RoomScanSource::load(int index) const {
  const CleanView view = cleanView(index);
  RgbdFrame frame;
  frame.index = index;
  frame.timestamp = path_[size_t(index)].timestamp;
  frame.T_world_cam_given = path_[size_t(index)].T_world_cam;
  frame.name = "room_" + std::to_string(index);
  applySensor(view, options_.sensor, options_.seed, index, frame);
  return frame;
}

std::string RoomScanSource::description() const {
  return "synthetic room 8 x 6 x 2.6 m, " + std::to_string(options_.frames) + " frames " +
         std::to_string(options_.width) + "x" + std::to_string(options_.height) + ", seed " +
         std::to_string(options_.seed) + (options_.sensor.noise ? ", Kinect v1 noise" : ", no noise");
}

}  // namespace vf::synth
