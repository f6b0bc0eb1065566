#pragma once
// One input frame as the bake sees it, and the per-sample test that decides whether (and how
// much) a frame's pixel may colour a surface point. Plain views and VF_HD functions, so that a
// CUDA backend can run the same per-texel code later (DESIGN.md, "One kernel, two backends").
#include <cmath>
#include <cstdint>

#include "core/image.h"
#include "core/intrinsics.h"
#include "core/math.h"

namespace vf {

struct BakeView {
  Rigid3f T_cam_world = Rigid3f::identity();
  Vec3f centre_world{0, 0, 0};   // the camera's optical centre
  Intrinsics color_k;            // of `color` (the depth camera scaled to the colour size)
  ImageView<const Rgb8> color;   // sRGB
  Intrinsics depth_k;
  ImageView<const float> depth;  // metres, 0 = no reading
  ImageView<const uint8_t> mask; // at the depth size; nonzero = never paint from here (people); may be empty
  float quality = 1.f;           // 0..1: lower for blurred frames
  Vec3f gain{1, 1, 1};           // exposure: multiplies the frame's colour to match the others
};

struct BakeSampleParams {
  float depth_tolerance_m = 0.04f;    // a point is visible when the frame's depth is within this ...
  float depth_tolerance_rel = 0.02f;  // ... plus this share of the distance
  // Views more grazing than this (or from behind, by the face's normal) weigh 1 % of a frontal
  // one: used only where nothing better sees the point. They are not refused: the depth test
  // decides visibility, and on noisy surfaces (Kinect depth at 3-4 m) the faces' normals
  // scatter so much that a quarter of TUM fr1/xyz's texels faced away from every frame that
  // saw them.
  float min_cos = 0.15f;
  float border_px = 16.f;             // weights fade to zero over this many pixels at the image border
};

// Whether `p` (world) is seen by `view` where nothing stands in front of it: inside the depth
// image, a depth reading there within tolerance of p's distance, and no reading in the 3x3
// pixels around that is nearer by more than the tolerance (a silhouette's edge, where the
// coarser depth and the colour image disagree about who is in front). Masked pixels fail too.
// Sets the point's depth-image pixel and camera z.
VF_HD bool visibleIn(const BakeView& view, const BakeSampleParams& s, Vec3f p, float& z) {
  const Vec3f q = view.T_cam_world * p;
  z = q.z;
  if (q.z <= 0.05f) return false;
  float u, v;
  view.depth_k.projectAnyDepth(q, u, v);
  const int x = int(floorf(u + 0.5f)), y = int(floorf(v + 0.5f));
  if (x < 1 || y < 1 || x >= view.depth.width - 1 || y >= view.depth.height - 1) return false;
  const float tolerance = s.depth_tolerance_m + s.depth_tolerance_rel * q.z;
  const float d = view.depth(x, y);
  if (!(d > 0.f) || fabsf(d - q.z) > tolerance) return false;
  for (int dy = -1; dy <= 1; ++dy)
    for (int dx = -1; dx <= 1; ++dx) {
      const float n = view.depth(x + dx, y + dy);
      if (n > 0.f && n < q.z - tolerance) return false;
      if (view.mask.data && view.mask(x + dx, y + dy)) return false;
    }
  return true;
}

// How much a view at `cos_view` (normal against the direction to the camera) counts.
VF_HD float facingWeight(float cos_view, const BakeSampleParams& s) {
  return cos_view >= s.min_cos ? cos_view : 0.01f * s.min_cos;
}

// The colour (sRGB 0-255, times the view's gain) view sees at p, bilinear at the colour size,
// and its weight: the frame's quality, how frontal (facingWeight) and how many colour pixels per
// metre of surface, faded at the image border. False when p is not visible or out of the colour
// image.
VF_HD bool sampleView(const BakeView& view, const BakeSampleParams& s, Vec3f p, Vec3f n, Vec3f& rgb,
                             float& weight) {
  float z;
  if (!visibleIn(view, s, p, z)) return false;
  const Vec3f to_cam = view.centre_world - p;
  const float dist = norm(to_cam);
  const float facing = facingWeight(dot(n, to_cam) / fmaxf(dist, 1e-6f), s);
  float u, v;
  view.color_k.projectAnyDepth(view.T_cam_world * p, u, v);
  const int w = view.color.width, h = view.color.height;
  if (!(u >= 0.f && v >= 0.f && u <= float(w - 1) && v <= float(h - 1))) return false;
  const int x0 = int(u), y0 = int(v);
  const int x1 = x0 + 1 < w ? x0 + 1 : x0, y1 = y0 + 1 < h ? y0 + 1 : y0;
  const float fx = u - float(x0), fy = v - float(y0);
  const Rgb8 a = view.color(x0, y0), b = view.color(x1, y0), c = view.color(x0, y1), d = view.color(x1, y1);
  auto mix = [&](float ca, float cb, float cc, float cd) {
    return (ca * (1.f - fx) + cb * fx) * (1.f - fy) + (cc * (1.f - fx) + cd * fx) * fy;
  };
  rgb = {mix(a.r, b.r, c.r, d.r) * view.gain.x, mix(a.g, b.g, c.g, d.g) * view.gain.y, mix(a.b, b.b, c.b, d.b) * view.gain.z};
  const float edge = fminf(fminf(u, float(w - 1) - u), fminf(v, float(h - 1) - v));
  const float fade = fminf(1.f, (edge + 1.f) / s.border_px);
  const float pixels_per_m = view.color_k.fx / z;
  weight = view.quality * facing * pixels_per_m * fade;
  return true;
}

}  // namespace vf
