#pragma once
// Ray casting the room: exact depth (z), normal and colour per pixel, and the Kinect v1 sensor
// model that turns them into what a depth camera delivers.
#include <cstdint>
#include <vector>

#include "core/frame.h"
#include "room_geometry.h"

namespace vf::synth {

// The pyramid of rays through the pixel rectangle [u0, u1] x [v0, v1] (pixel centres at
// integers) of a camera at T_world_cam.
struct Frustum {
  Vec3 origin, forward;
  Vec3 side_normals[4];  // pointing inwards
  // False only when the box lies entirely outside the sides, or nearer than `near_m` or further
  // than `far_m` along the optical axis.
  bool meetsBox(const Vec3& lo, const Vec3& hi, float near_m = 0.f, float far_m = 1e30f) const;
};
Frustum pixelFrustum(const Intrinsics& k, const Pose& T_world_cam, float u0, float u1, float v0, float v1);

// Per 16x16 pixel tile, the primitives whose bounds meet the tile's frustum (the shell always):
// a ray then tests a handful of the ~60 primitives.
class TileCuller {
 public:
  static constexpr int kTile = 16;
  TileCuller(const Room& room, const Intrinsics& k, const Pose& T_world_cam);
  // Candidates for the ray through pixel (x, y), which must lie in the image.
  const std::vector<int>& candidates(int x, int y) const {
    return lists_[size_t((y / kTile) * tiles_x_ + x / kTile)];
  }
  int tilesX() const { return tiles_x_; }
  int tilesY() const { return tiles_y_; }
  const std::vector<int>& tile(int tx, int ty) const { return lists_[size_t(ty * tiles_x_ + tx)]; }

 private:
  int tiles_x_ = 0, tiles_y_ = 0;
  std::vector<std::vector<int>> lists_;
};

// What a perfect camera sees: z depth in metres (0 where no surface), the cosine between the
// ray and the surface normal, the primitive hit (-1 none) and the surface colour.
struct CleanView {
  DepthImage depth;
  ColorImage color;
  std::vector<float> cos_incidence;
  std::vector<int16_t> primitive;
};
CleanView renderClean(const Room& room, const Intrinsics& k, const Pose& T_world_cam);

// Kinect v1 depth (Nguyen, Izadi and Lovell 2012): axial noise sigma(z) = 0.0012 +
// 0.0019 (z - 0.4)^2 m, no reading nearer than 0.4 m, beyond 4.5 m or at more than 75 degrees
// of incidence, a few random dropouts, and the 1/5000 m steps of a TUM depth PNG. Colour gets
// mild Gaussian noise. With `noise` off the frame is the perfect camera's (every surface within
// range, exact depth and colour).
//
// The defaults are the room's sensor. kinectV1Sensor() adds what a real Kinect v1 does on top
// (Khoshelham and Elberink 2012; Smisek, Jancosek and Pajdla 2011): depth comes from a disparity
// measured in steps, so it is rounded to the nearest step of 1/z, 2.85e-3 / m, which is
// 2.85e-3 z^2 m in depth (2.9 mm at 1 m, 2.6 cm at 3 m); and each pixel reads a fixed few
// millimetres per metre too far or too near (its depth distortion), the same in every frame.
struct SensorModel {
  bool noise = true;
  float min_range_m = 0.4f, max_range_m = 4.5f;
  float max_incidence_deg = 75.f;
  float dropout_fraction = 0.004f;
  float color_sigma = 2.f;  // 8-bit levels
  float depth_step_m = 1.f / 5000.f;
  float disparity_step_per_m = 0.f;  // > 0: depth rounded to the nearest step of 1/z first
  float bias_per_m = 0.f;            // scale of depthBiasPattern: depth *= 1 + bias_per_m * pattern
};
float axialSigma(float z_m);
SensorModel kinectV1Sensor();  // disparity steps of 2.85e-3 / m, bias scale 3 mm/m

// The per-pixel depth distortion's shape, a function of the pixel only (the same in every frame,
// for every seed; the same picture at any image size): a bowl, deeper towards the corners, a
// smooth tilt, and a faint fixed per-pixel grain; between about -0.8 and 1.6.
float depthBiasPattern(int x, int y, int width, int height);

// z rounded to the nearest level 1 / (k step_per_m), k an integer: the disparity's steps.
float quantiseDisparity(float z_m, float step_per_m);

// The sensor's frame from the perfect view; noise is a function of (seed, frame_index, pixel).
void applySensor(const CleanView& view, const SensorModel& sensor, uint64_t seed, int frame_index, RgbdFrame& frame);

}  // namespace vf::synth
