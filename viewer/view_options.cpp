#include "viewer/view_options.h"

#include <algorithm>
#include <cmath>
#include <filesystem>

#include "core/error.h"
#include "core/text_fields.h"
#include "viewer/view_style.h"

namespace vf::viewer {
namespace {

// Within +-2^30: sizes and indices, whose products must not overflow.
bool parseBoundedInt(const std::string& s, int& out) {
  return parseInt(s, out) && out >= -(1 << 30) && out <= (1 << 30);
}

}  // namespace

CameraSpec parseCameraSpec(const std::string& text) {
  CameraSpec spec;
  if (text == "front") return spec;
  if (text == "top") {
    spec.preset = CameraPreset::kTop;
    return spec;
  }
  if (text == "side") {
    spec.preset = CameraPreset::kSide;
    return spec;
  }
  const std::string prefix = "trajectory:";
  if (text.rfind(prefix, 0) == 0 && parseBoundedInt(text.substr(prefix.size()), spec.frame) && spec.frame >= 0) {
    spec.preset = CameraPreset::kTrajectory;
    return spec;
  }
  throw Error("--camera '" + text + "': expected front, top, side or trajectory:N (N = pose index, from 0)");
}

SliceSpec parseSliceSpec(const std::string& text) {
  SliceSpec spec;
  for (const char* prefix : {"height=", "height:"})
    if (text.rfind(prefix, 0) == 0) {
      if (!parseFiniteFloat(text.substr(7), spec.value_m))
        throw Error("--slice '" + text + "': expected height=METRES above the floor (e.g. height=1.0)");
      spec.enabled = spec.level = true;
      return spec;
    }
  const bool axis_ok = text.size() >= 3 && text[1] == ':' && (text[0] == 'x' || text[0] == 'y' || text[0] == 'z');
  if (!axis_ok || !parseFiniteFloat(text.substr(2), spec.value_m))
    throw Error("--slice '" + text + "': expected height=METRES (a floor plan that high above the floor, e.g. "
                "height=1.0) or AXIS:VALUE with AXIS x, y or z and VALUE in metres along that world axis (e.g. z:1.5)");
  spec.enabled = true;
  spec.axis = text[0] - 'x';
  return spec;
}

void parseWindowSize(const std::string& text, int& width, int& height) {
  const size_t x = text.find('x');
  int w = 0, h = 0;
  if (x == std::string::npos || !parseBoundedInt(text.substr(0, x), w) || !parseBoundedInt(text.substr(x + 1), h) || w < 16 ||
      h < 16 || w > 16384 || h > 16384)
    throw Error("--size '" + text + "': expected WIDTHxHEIGHT in pixels, each 16..16384 (e.g. 1280x720)");
  width = w;
  height = h;
}

std::string defaultTrajectoryPath(const std::string& scene_path) { return besideScene(scene_path, ".txt"); }

std::string besideScene(const std::string& scene_path, const std::string& suffix) {
  const std::filesystem::path p(scene_path);
  return (p.parent_path() / (p.stem().string() + suffix)).string();
}

const char* axisName(int axis) { return axis == 0 ? "x" : axis == 1 ? "y" : "z"; }

PictureFormat pictureFormatFromPath(const std::string& path) {
  std::string ext = std::filesystem::path(path).extension().string();
  std::transform(ext.begin(), ext.end(), ext.begin(), [](unsigned char c) { return char(std::tolower(c)); });
  if (ext == ".png") return PictureFormat::kPng;
  if (ext == ".jpg" || ext == ".jpeg") return PictureFormat::kJpeg;
  throw Error("--screenshot " + path + ": pictures are written as PNG or JPEG; name the file .png, .jpg or .jpeg");
}

FrameCamera frameCamera(const Intrinsics& k) {
  if (!k.valid()) return {kTrajectoryFovYDeg, 4.0 / 3.0};
  const double half_h = 0.5 * k.height / k.fy, half_w = 0.5 * k.width / k.fx;
  return {2.0 * std::atan(half_h) * 180.0 / M_PI, half_w / half_h};
}

CameraPreset cameraFacingSlice(const SliceSpec& slice, Vec3f up, Vec3f forward) {
  if (slice.level) return CameraPreset::kTop;
  const Vec3f right = cross(forward, up);
  const auto along = [&](Vec3f d) { return std::fabs(slice.axis == 0 ? d.x : slice.axis == 1 ? d.y : d.z); };
  const float front = along(forward), side = along(right), top = along(up);
  if (top >= front && top >= side) return CameraPreset::kTop;
  return side > front ? CameraPreset::kSide : CameraPreset::kFront;
}

}  // namespace vf::viewer
