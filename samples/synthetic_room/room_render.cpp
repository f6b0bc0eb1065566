#include "room_render.h"

#include <tbb/parallel_for.h>

#include <algorithm>
#include <cmath>

#include "room_random.h"
#include "room_texture.h"

namespace vf::synth {
namespace {

Vec3 cameraRay(const Intrinsics& k, float u, float v) { return Vec3((u - k.cx) / k.fx, (v - k.cy) / k.fy, 1.f); }

// False when the box lies entirely on the negative side of the plane through `origin` with
// normal `n` (the corner furthest along n is behind it).
bool boxInFront(const Vec3& lo, const Vec3& hi, const Vec3& origin, const Vec3& n) {
  const Vec3 far_corner(n.x() > 0 ? hi.x() : lo.x(), n.y() > 0 ? hi.y() : lo.y(), n.z() > 0 ? hi.z() : lo.z());
  return n.dot(far_corner - origin) >= 0.f;
}

}  // namespace

Frustum pixelFrustum(const Intrinsics& k, const Pose& T, float u0, float u1, float v0, float v1) {
  Frustum f;
  const Eigen::Matrix3f R = T.linear().cast<float>();
  f.origin = T.translation().cast<float>();
  f.forward = R.col(2);
  const Vec3 corner[4] = {R * cameraRay(k, u0, v0), R * cameraRay(k, u1, v0), R * cameraRay(k, u1, v1),
                          R * cameraRay(k, u0, v1)};
  const Vec3 middle = R * cameraRay(k, 0.5f * (u0 + u1), 0.5f * (v0 + v1));
  for (int e = 0; e < 4; ++e) {
    Vec3 n = corner[e].cross(corner[(e + 1) % 4]);
    f.side_normals[e] = n.dot(middle) < 0 ? Vec3(-n) : n;
  }
  return f;
}

bool Frustum::meetsBox(const Vec3& lo, const Vec3& hi, float near_m, float far_m) const {
  if (!boxInFront(lo, hi, origin + near_m * forward, forward)) return false;
  if (!boxInFront(lo, hi, origin + far_m * forward, -forward)) return false;
  for (const Vec3& n : side_normals)
    if (!boxInFront(lo, hi, origin, n)) return false;
  return true;
}

TileCuller::TileCuller(const Room& room, const Intrinsics& k, const Pose& T) {
  tiles_x_ = (k.width + kTile - 1) / kTile;
  tiles_y_ = (k.height + kTile - 1) / kTile;
  lists_.resize(size_t(tiles_x_ * tiles_y_));
  for (int ty = 0; ty < tiles_y_; ++ty)
    for (int tx = 0; tx < tiles_x_; ++tx) {
      const float u0 = float(tx * kTile) - 0.5f, u1 = float(std::min((tx + 1) * kTile, k.width)) - 0.5f;
      const float v0 = float(ty * kTile) - 0.5f, v1 = float(std::min((ty + 1) * kTile, k.height)) - 0.5f;
      const Frustum f = pixelFrustum(k, T, u0, u1, v0, v1);
      std::vector<int>& list = lists_[size_t(ty * tiles_x_ + tx)];
      for (int i = 0; i < int(room.primitives.size()); ++i) {
        const Primitive& p = room.primitives[size_t(i)];
        if (p.kind == Primitive::Kind::kShell || f.meetsBox(p.lo, p.hi)) list.push_back(i);
      }
    }
}

CleanView renderClean(const Room& room, const Intrinsics& k, const Pose& T) {
  CleanView view;
  view.depth.resize(k.width, k.height, 0.f);
  view.color.resize(k.width, k.height, Rgb8{0, 0, 0, 255});
  view.cos_incidence.assign(size_t(k.width) * size_t(k.height), 0.f);
  view.primitive.assign(size_t(k.width) * size_t(k.height), int16_t(-1));
  const TileCuller culler(room, k, T);
  const Eigen::Matrix3f R = T.linear().cast<float>();
  const Vec3 origin = T.translation().cast<float>();
  tbb::parallel_for(0, culler.tilesX() * culler.tilesY(), [&](int tile) {
    const int tx = tile % culler.tilesX(), ty = tile / culler.tilesX();
    const std::vector<int>& candidates = culler.tile(tx, ty);
    for (int y = ty * TileCuller::kTile; y < std::min((ty + 1) * TileCuller::kTile, k.height); ++y)
      for (int x = tx * TileCuller::kTile; x < std::min((tx + 1) * TileCuller::kTile, k.width); ++x) {
        const Vec3 ray = cameraRay(k, float(x), float(y));
        const float ray_norm = ray.norm();
        const Vec3 dir = R * (ray / ray_norm);
        Hit hit;
        if (!room.intersect(origin, dir, 1e3f, hit, &candidates)) continue;
        const size_t i = size_t(y) * size_t(k.width) + size_t(x);
        view.depth(x, y) = hit.t / ray_norm;  // z = t * cos(angle to the optical axis)
        view.cos_incidence[i] = -hit.normal.dot(dir);
        view.primitive[i] = int16_t(hit.primitive);
        const Vec3 point = origin + hit.t * dir;
        const Vec3 c = surfaceColor(room.primitives[size_t(hit.primitive)], point, hit.normal);
        view.color(x, y) = Rgb8{uint8_t(c.x() + 0.5f), uint8_t(c.y() + 0.5f), uint8_t(c.z() + 0.5f), 255};  // c in 0..255
      }
  });
  return view;
}

float axialSigma(float z) { return 0.0012f + 0.0019f * (z - 0.4f) * (z - 0.4f); }

SensorModel kinectV1Sensor() {
  SensorModel s;
  s.disparity_step_per_m = 2.85e-3f;
  s.bias_per_m = 3e-3f;
  return s;
}

float depthBiasPattern(int x, int y, int width, int height) {
  const float u = 2.f * (float(x) + 0.5f) / float(width) - 1.f, v = 2.f * (float(y) + 0.5f) / float(height) - 1.f;
  const float bowl = 1.5f * (0.5f * (u * u + v * v) - 1.f / 3.f);  // mean 0 over the image
  const float tilt = 0.5f * std::sin(2.3f * u + 0.7f) * std::cos(1.9f * v - 0.4f);
  const float grain = 0.25f * (2.f * unitFloat(hash4(0xB1A5, uint64_t(x), uint64_t(y), 0)) - 1.f);
  return bowl + tilt + grain;
}

float quantiseDisparity(float z, float step_per_m) {
  const double level = std::round(1.0 / (double(z) * double(step_per_m)));
  return level > 0 ? float(1.0 / (level * double(step_per_m))) : 0.f;
}

void applySensor(const CleanView& view, const SensorModel& sensor, uint64_t seed, int frame_index, RgbdFrame& frame) {
  const int w = view.depth.width(), h = view.depth.height();
  frame.depth.resize(w, h, 0.f);
  frame.color = view.color;
  const float min_cos = std::cos(sensor.max_incidence_deg * float(M_PI) / 180.f);
  const uint64_t frame_key = hash4(seed, uint64_t(frame_index), 0x5EED, 0);
  tbb::parallel_for(0, h, [&](int y) {
    for (int x = 0; x < w; ++x) {
      const size_t i = size_t(y) * size_t(w) + size_t(x);
      const float z = view.depth(x, y);
      if (!sensor.noise) {
        frame.depth(x, y) = z;
        continue;
      }
      // 16 bits of noise per colour channel and 16 for the dropout from one hash, the depth
      // noise from a second.
      const uint64_t base = splitmix64(frame_key + uint64_t(i) * 0xD1B54A32D192ED03ull);
      const uint64_t color_bits = base;
      Rgb8& c = frame.color(x, y);
      uint8_t* channel[3] = {&c.r, &c.g, &c.b};
      for (int ch = 0; ch < 3; ++ch) {
        const float v = float(*channel[ch]) + sensor.color_sigma * roughGaussian(uint32_t(color_bits >> (16 * ch)));
        *channel[ch] = uint8_t(std::clamp(v, 0.f, 255.f) + 0.5f);
      }
      if (z < sensor.min_range_m || z > sensor.max_range_m) continue;
      if (view.cos_incidence[i] < min_cos) continue;
      if (float(base >> 48) * (1.f / 65536.f) < sensor.dropout_fraction) continue;
      const float biased = sensor.bias_per_m != 0.f ? z * (1.f + sensor.bias_per_m * depthBiasPattern(x, y, w, h)) : z;
      float noisy = biased + axialSigma(z) * gaussian(splitmix64(base));
      if (sensor.disparity_step_per_m > 0.f) noisy = quantiseDisparity(noisy, sensor.disparity_step_per_m);
      frame.depth(x, y) = std::round(noisy / sensor.depth_step_m) * sensor.depth_step_m;
    }
  });
}

}  // namespace vf::synth
