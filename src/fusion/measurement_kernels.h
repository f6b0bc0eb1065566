#pragma once
// Surface measurement (KinectFusion section 3.2): bilateral filter, depth pyramid, vertex and
// normal maps. One functor per rule, run per pixel by either backend.
#include "core/image.h"
#include "core/intrinsics.h"
#include "fusion/fast_math.h"

namespace vf {

// Edge-preserving depth smoothing, eq. (2): weights fall off with pixel distance and depth
// difference; invalid pixels neither receive nor give. Both Gaussians come from tables built
// once on the host (make()), so a tap costs a multiply and two loads instead of an exp; the
// range table stops at 3 sigma, beyond which a neighbour's weight (< 1.2 %) is dropped.
struct BilateralFilterKernel {
  static constexpr int kMaxRadius = 3;
  static constexpr int kRangeTableSize = 256;
  ImageView<const float> depth_in;
  ImageView<float> depth_out;
  int radius = 2;
  float min_depth_m = 0, max_depth_m = 0;
  float spatial_weight[(2 * kMaxRadius + 1) * (2 * kMaxRadius + 1)] = {};
  float range_weight[kRangeTableSize] = {};
  float range_index_per_m2 = 0;  // squared depth difference -> table index

  static BilateralFilterKernel make(int radius_px, float sigma_px, float sigma_m, float min_depth_m,
                                    float max_depth_m) {
    BilateralFilterKernel k;
    k.radius = radius_px;
    k.min_depth_m = min_depth_m;
    k.max_depth_m = max_depth_m;
    for (int dy = -radius_px; dy <= radius_px; ++dy)
      for (int dx = -radius_px; dx <= radius_px; ++dx)
        k.spatial_weight[(dy + kMaxRadius) * (2 * kMaxRadius + 1) + dx + kMaxRadius] =
            fastExp(-float(dx * dx + dy * dy) / (2.f * sigma_px * sigma_px));
    const float max_d2 = 9.f * sigma_m * sigma_m;
    k.range_index_per_m2 = float(kRangeTableSize - 1) / max_d2;
    for (int i = 0; i < kRangeTableSize; ++i)
      k.range_weight[i] = fastExp(-(float(i) / k.range_index_per_m2) / (2.f * sigma_m * sigma_m));
    return k;
  }

  // Pixels per work item: 1 (CUDA), or kLanes neighbours of one row (the CPU), which run in
  // vector lanes where their windows lie inside the image. Either gives the same bits.
  static constexpr int kLanes = 8;
  int pixels_per_item = 1;

  VF_HD int segmentsPerRow() const { return (depth_in.width + kLanes - 1) / kLanes; }
  VF_HD int itemCount() const {
    return pixels_per_item == 1 ? depth_in.width * depth_in.height : segmentsPerRow() * depth_in.height;
  }

  VF_HD void operator()(int item) const {
    if (pixels_per_item == 1) {
      filterPixel(item);
      return;
    }
    const int y = item / segmentsPerRow(), x0 = (item % segmentsPerRow()) * kLanes;
    if (y < radius || y + radius >= depth_in.height || x0 < radius || x0 + kLanes + radius > depth_in.width) {
      for (int j = 0; j < kLanes && x0 + j < depth_in.width; ++j) filterPixel(y * depth_in.width + x0 + j);
      return;
    }
    filterInterior(x0, y);
  }

  // kLanes pixels from (x0, y) whose windows lie inside the image: filterPixel's sums, tap by
  // tap in the same order, with a refused tap adding zero instead of being skipped. The
  // neighbours of the lanes are contiguous loads; only the range-table reads are gathers. (An
  // AVX2 gather instruction for them was no faster than the compiler's scalar loads, 2026-12-04.)
  VF_HD void filterInterior(int x0, int y) const {
    float d0[kLanes], sum[kLanes], weight_sum[kLanes];
    for (int j = 0; j < kLanes; ++j) d0[j] = depth_in(x0 + j, y), sum[j] = 0.f, weight_sum[j] = 0.f;
    for (int dy = -radius; dy <= radius; ++dy) {
      const float* row = &depth_in(x0, y + dy);
      const float* spatial = spatial_weight + (dy + kMaxRadius) * (2 * kMaxRadius + 1) + kMaxRadius;
      for (int dx = -radius; dx <= radius; ++dx) {
        float range[kLanes];
        int index[kLanes], use[kLanes];
        VF_SIMD_LOOP
        for (int j = 0; j < kLanes; ++j) {
          const float d = row[j + dx];
          const float dd = d - d0[j];
          const float scaled = dd * dd * range_index_per_m2;
          use[j] = (d >= min_depth_m) & (d <= max_depth_m) & (scaled < float(kRangeTableSize));
          index[j] = use[j] ? int(scaled) : 0;
        }
        for (int j = 0; j < kLanes; ++j) range[j] = range_weight[index[j]];
        // The neighbours are read from the row again rather than kept in an array across the
        // table reads: GCC kept such an array on the stack, written in two halves and read
        // whole, a store-forwarding stall that was 60 % of the filter's time.
        VF_SIMD_LOOP
        for (int j = 0; j < kLanes; ++j) {
          const float w = spatial[dx] * range[j], weighted = w * row[j + dx];
          sum[j] += use[j] ? weighted : 0.f;
          weight_sum[j] += use[j] ? w : 0.f;
        }
      }
    }
    for (int j = 0; j < kLanes; ++j) {
      const bool valid = d0[j] >= min_depth_m && d0[j] <= max_depth_m;
      depth_out(x0 + j, y) = valid ? sum[j] / weight_sum[j] : 0.f;  // weight_sum >= 1 from the centre
    }
  }

  VF_HD void filterPixel(int i) const {
    const int x = i % depth_in.width, y = i / depth_in.width;
    const float d0 = depth_in[i];
    if (!(d0 >= min_depth_m && d0 <= max_depth_m)) {
      depth_out[i] = 0.f;
      return;
    }
    float sum = 0.f, weight_sum = 0.f;
    const int y0 = y - radius < 0 ? 0 : y - radius, y1 = y + radius >= depth_in.height ? depth_in.height - 1 : y + radius;
    const int x0 = x - radius < 0 ? 0 : x - radius, x1 = x + radius >= depth_in.width ? depth_in.width - 1 : x + radius;
    for (int v = y0; v <= y1; ++v) {
      const float* row = &depth_in(0, v);
      const float* spatial = spatial_weight + (v - y + kMaxRadius) * (2 * kMaxRadius + 1) + kMaxRadius;
      for (int u = x0; u <= x1; ++u) {
        const float d = row[u];
        if (!(d >= min_depth_m && d <= max_depth_m)) continue;
        const float dd = d - d0;
        const int index = int(dd * dd * range_index_per_m2);
        if (index >= kRangeTableSize) continue;
        const float w = spatial[u - x] * range_weight[index];
        sum += w * d;
        weight_sum += w;
      }
    }
    depth_out[i] = sum / weight_sum;  // weight_sum >= 1 from the centre pixel
  }
};

// Half-resolution depth: mean of the 2x2 block's pixels within depth_jump of the first valid one
// (KinectFusion averages only samples within 3 sigma so edges do not blur across depth jumps).
struct DownsampleDepthKernel {
  ImageView<const float> fine;
  ImageView<float> coarse;
  float depth_jump_m = 0.09f;

  VF_HD int rowLength() const { return coarse.width; }
  VF_HD void operator()(int i) const { at(i % coarse.width, i / coarse.width, i); }
  VF_HD void at(int x, int y, int i) const {
    float ref = 0.f, sum = 0.f;
    int count = 0;
    for (int k = 0; k < 4; ++k) {
      const float d = fine(2 * x + (k & 1), 2 * y + (k >> 1));
      if (d <= 0.f) continue;
      if (count == 0) ref = d;
      if (fabsf(d - ref) > depth_jump_m) continue;
      sum += d;
      ++count;
    }
    coarse[i] = count > 0 ? sum / float(count) : 0.f;
  }
};

// Back-projection, eq. (3). Invalid pixels get the zero vector (z = 0 marks them).
struct VertexMapKernel {
  ImageView<const float> depth;
  ImageView<Vec3f> vertex;
  Intrinsics intrinsics;

  VF_HD int rowLength() const { return depth.width; }
  VF_HD void operator()(int i) const { at(i % depth.width, i / depth.width, i); }
  VF_HD void at(int x, int y, int i) const {
    const float d = depth[i];
    vertex[i] = d > 0.f ? intrinsics.backProject(float(x), float(y), d) : Vec3f{0.f, 0.f, 0.f};
  }
};

// Normals from central differences of the vertex map, eq. (4), oriented towards the camera.
// A neighbour further than max_jump_m away (a depth edge) invalidates the normal.
// Only every stride-th pixel in x and y gets one: ICP, their only reader, samples the level at
// that spacing (IcpParams::stride_px), and the other pixels' normals were three quarters of the
// work (fr1_xyz 4 % of the whole run's CPU time). The other pixels keep whatever they held.
struct NormalMapKernel {
  ImageView<const Vec3f> vertex;
  ImageView<Vec3f> normal;
  float max_jump_m = 0.05f;
  int stride_px = 1;

  VF_HD int itemCount() const { return stridedPixelCount(vertex.width, vertex.height, stride_px); }

  // Items walk the strided pixels (core/image.h stridedPixel): row by row, column by column.
  VF_HD int rowLength() const { return stridedColumns(vertex.width, stride_px); }
  VF_HD void operator()(int item) const { at(item % rowLength(), item / rowLength(), item); }
  VF_HD void at(int column, int row, int /*item*/) const {
    const int x = column * stride_px, y = row * stride_px, i = y * vertex.width + x;
    normal[i] = Vec3f{0.f, 0.f, 0.f};
    if (x < 1 || y < 1 || x >= vertex.width - 1 || y >= vertex.height - 1) return;
    const Vec3f c = vertex[i];
    const Vec3f l = vertex(x - 1, y), r = vertex(x + 1, y), u = vertex(x, y - 1), d = vertex(x, y + 1);
    if (c.z <= 0.f || l.z <= 0.f || r.z <= 0.f || u.z <= 0.f || d.z <= 0.f) return;
    if (fabsf(r.z - l.z) > max_jump_m || fabsf(d.z - u.z) > max_jump_m) return;
    Vec3f n = normalized(cross(r - l, d - u));
    if (dot(n, c) > 0.f) n = -n;
    normal[i] = n;
  }
};

// A larger colour image of the same view averaged down to the depth size by area: each depth
// pixel takes the mean of the colour it covers, partly covered colour pixels weighted by their
// share (OpenCV's INTER_AREA, which the readers used before colour was fused at full size).
struct DownsampleColorKernel {
  ImageView<const Rgb8> full;
  ImageView<Rgb8> out;
  VF_HD void operator()(int i) const {
    const int x = i % out.width, y = i / out.width;
    const float sx = float(full.width) / float(out.width), sy = float(full.height) / float(out.height);
    const float ax = float(x) * sx, bx = ax + sx, ay = float(y) * sy, by = ay + sy;
    float r = 0.f, g = 0.f, b = 0.f;
    for (int yy = int(ay); yy < full.height && float(yy) < by; ++yy) {
      const float wy = minFloat(float(yy + 1), by) - maxFloat(float(yy), ay);
      for (int xx = int(ax); xx < full.width && float(xx) < bx; ++xx) {
        const float w = wy * (minFloat(float(xx + 1), bx) - maxFloat(float(xx), ax));
        const Rgb8 c = full(xx, yy);
        r += w * float(c.r);
        g += w * float(c.g);
        b += w * float(c.b);
      }
    }
    const float inv_area = 1.f / (sx * sy);
    auto byte = [](float v) { return uint8_t(clampFloat(rintf(v), 0.f, 255.f)); };
    out[i] = Rgb8{byte(r * inv_area), byte(g * inv_area), byte(b * inv_area), 255};
  }
};

}  // namespace vf
