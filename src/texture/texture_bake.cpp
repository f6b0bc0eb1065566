// Face candidates, exposure gains, the texel pass per chart, gutter dilation.
#include "texture/texture_bake.h"

#include <tbb/blocked_range.h>
#include <tbb/combinable.h>
#include <tbb/parallel_for.h>

#include <algorithm>
#include <array>
#include <atomic>
#include <chrono>
#include <cmath>
#include <mutex>

#include "core/error.h"
#include "texture/mesh_adjacency.h"

namespace vf {
namespace {

constexpr int kMaxCandidates = 8;

struct FaceViews {
  std::array<int32_t, kMaxCandidates> view;
  int count = 0;
};

double secondsSince(std::chrono::steady_clock::time_point t0) {
  return std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count();
}

Vec3f faceNormal(const TriangleMesh& mesh, size_t f) {
  const auto& t = mesh.triangles[f];
  const Vec3f a = mesh.positions[size_t(t[0])], b = mesh.positions[size_t(t[1])], c = mesh.positions[size_t(t[2])];
  return normalized(cross(b - a, c - a));
}

// The views that see most of a face best: seven points (corners, edge midpoints, centre) tested
// for visibility; score = the sample weight at the centre times the share of points seen.
std::vector<FaceViews> selectViews(const TriangleMesh& mesh, const std::vector<BakeView>& views, const BakeOptions& o,
                                   size_t* unseen) {
  std::vector<FaceViews> out(mesh.triangleCount());
  const int keep = std::min(o.views_per_face, kMaxCandidates);
  tbb::combinable<size_t> none([] { return size_t(0); });
  tbb::parallel_for(tbb::blocked_range<size_t>(0, mesh.triangleCount(), 256), [&](const tbb::blocked_range<size_t>& r) {
    for (size_t f = r.begin(); f != r.end(); ++f) {
      const auto& t = mesh.triangles[f];
      const Vec3f a = mesh.positions[size_t(t[0])], b = mesh.positions[size_t(t[1])], c = mesh.positions[size_t(t[2])];
      const Vec3f centre = (a + b + c) * (1.f / 3.f);
      const Vec3f n = faceNormal(mesh, f);
      const Vec3f points[7] = {a, b, c, (a + b) * 0.5f, (b + c) * 0.5f, (a + c) * 0.5f, centre};
      std::array<float, kMaxCandidates> score{};
      FaceViews& fv = out[f];
      for (int32_t v = 0; v < int32_t(views.size()); ++v) {
        const BakeView& view = views[size_t(v)];
        const Vec3f to_cam = view.centre_world - centre;
        const float dist = norm(to_cam);
        const float facing = facingWeight(dot(n, to_cam) / std::max(dist, 1e-6f), o.sample);
        const Vec3f q = view.T_cam_world * centre;
        if (q.z <= 0.05f) continue;
        // Cheap rejection: the centre far outside the image (by more than the face's size).
        float u, w;
        view.depth_k.projectAnyDepth(q, u, w);
        const float reach = view.depth_k.fx * (norm(a - centre) + norm(b - centre) + norm(c - centre)) / q.z;
        if (u < -reach || w < -reach || u > float(view.depth_k.width) + reach || w > float(view.depth_k.height) + reach)
          continue;
        // The score with every point seen: when that cannot enter a full list, skip the tests.
        const float bound = view.quality * facing * (view.color_k.fx / q.z);
        if (fv.count == keep && bound <= score[size_t(keep - 1)]) continue;
        int seen = 0;
        float z;
        for (const Vec3f& p : points) seen += visibleIn(view, o.sample, p, z) ? 1 : 0;
        if (seen == 0) continue;
        const float s = bound * float(seen) / 7.f;
        // Insert into the few best, kept sorted by score.
        int i = fv.count < keep ? fv.count++ : keep;
        if (i == keep && s <= score[size_t(keep - 1)]) continue;
        if (i == keep) i = keep - 1;
        while (i > 0 && score[size_t(i - 1)] < s) {
          score[size_t(i)] = score[size_t(i - 1)];
          fv.view[size_t(i)] = fv.view[size_t(i - 1)];
          --i;
        }
        score[size_t(i)] = s;
        fv.view[size_t(i)] = v;
      }
      if (fv.count == 0) ++none.local();
    }
  });
  *unseen = none.combine(std::plus<size_t>());
  return out;
}

// Each face's candidates topped up with its edge neighbours' (their best first) to the most a
// face keeps: neighbouring faces then blend from mostly the same frames, and the texture shows
// no seam along every edge where the two faces' own choices differ (the views through a window
// came out facet by facet).
std::vector<FaceViews> shareWithNeighbours(const std::vector<FaceViews>& own,
                                           const std::vector<std::array<int32_t, 3>>& nb) {
  std::vector<FaceViews> out(own.size());
  tbb::parallel_for(tbb::blocked_range<size_t>(0, own.size(), 1024), [&](const tbb::blocked_range<size_t>& r) {
    for (size_t f = r.begin(); f != r.end(); ++f) {
      FaceViews v = own[f];
      for (int rank = 0; rank < kMaxCandidates && v.count < kMaxCandidates; ++rank)
        for (int32_t g : nb[f]) {
          if (g < 0 || rank >= own[size_t(g)].count || v.count >= kMaxCandidates) continue;
          const int32_t view = own[size_t(g)].view[size_t(rank)];
          if (std::find(v.view.begin(), v.view.begin() + v.count, view) == v.view.begin() + v.count)
            v.view[size_t(v.count++)] = view;
        }
      out[f] = v;
    }
  });
  return out;
}

// Per-view gains that bring each frame's colour to the mean of the frames seeing the same face
// centres (two rounds), clamped to +-40 %: auto-exposure changes between frames otherwise show
// as patches where the best frame changes from one face to the next.
void equaliseExposure(const TriangleMesh& mesh, const std::vector<FaceViews>& candidates, std::vector<BakeView>& views,
                      const BakeOptions& o) {
  for (int round = 0; round < 2; ++round) {
    struct Sums {
      std::vector<double> own, ref;  // 3 per view
    };
    tbb::combinable<Sums> sums([&] { return Sums{std::vector<double>(views.size() * 3, 0.0), std::vector<double>(views.size() * 3, 0.0)}; });
    tbb::parallel_for(tbb::blocked_range<size_t>(0, mesh.triangleCount(), 512), [&](const tbb::blocked_range<size_t>& r) {
      Sums& s = sums.local();
      for (size_t f = r.begin(); f != r.end(); ++f) {
        const FaceViews& fv = candidates[f];
        if (fv.count < 2) continue;
        const auto& t = mesh.triangles[f];
        const Vec3f centre =
            (mesh.positions[size_t(t[0])] + mesh.positions[size_t(t[1])] + mesh.positions[size_t(t[2])]) * (1.f / 3.f);
        const Vec3f n = faceNormal(mesh, f);
        Vec3f rgb[kMaxCandidates];
        int ids[kMaxCandidates], k = 0;
        Vec3f mean{0, 0, 0};
        for (int i = 0; i < fv.count; ++i) {
          float w;
          if (!sampleView(views[size_t(fv.view[size_t(i)])], o.sample, centre, n, rgb[k], w)) continue;
          ids[k] = fv.view[size_t(i)];
          mean = mean + rgb[k];
          ++k;
        }
        if (k < 2) continue;
        mean = mean * (1.f / float(k));
        for (int i = 0; i < k; ++i) {
          const size_t v = size_t(ids[i]) * 3;
          s.own[v] += rgb[i].x, s.own[v + 1] += rgb[i].y, s.own[v + 2] += rgb[i].z;
          s.ref[v] += mean.x, s.ref[v + 1] += mean.y, s.ref[v + 2] += mean.z;
        }
      }
    });
    Sums total{std::vector<double>(views.size() * 3, 0.0), std::vector<double>(views.size() * 3, 0.0)};
    sums.combine_each([&](const Sums& s) {
      for (size_t i = 0; i < s.own.size(); ++i) total.own[i] += s.own[i], total.ref[i] += s.ref[i];
    });
    for (size_t v = 0; v < views.size(); ++v) {
      float g[3];
      for (int c = 0; c < 3; ++c) {
        const double own = total.own[v * 3 + size_t(c)], ref = total.ref[v * 3 + size_t(c)];
        g[c] = own > 1000.0 ? float(std::clamp(ref / own, 0.6, 1.4)) : 1.f;  // too little overlap: leave it
      }
      views[v].gain = {views[v].gain.x * g[0], views[v].gain.y * g[1], views[v].gain.z * g[2]};
    }
  }
}

// The colour of one texel at world point p on a face with normal n: the best `blend` of the
// face's candidate views that see p, weighted by their sample weight squared.
bool blendTexel(const std::vector<BakeView>& views, const FaceViews& fv, const BakeOptions& o, Vec3f p, Vec3f n,
                Vec3f& out) {
  Vec3f rgb[kMaxCandidates];
  float weight[kMaxCandidates];
  int k = 0;
  for (int i = 0; i < fv.count; ++i)
    if (sampleView(views[size_t(fv.view[size_t(i)])], o.sample, p, n, rgb[k], weight[k])) ++k;
  if (k == 0) return false;
  // Keep the `blend` heaviest (k is at most 8: selection by swaps).
  const int blend = std::min(k, std::max(1, o.blend_views));
  for (int i = 0; i < blend; ++i)
    for (int j = i + 1; j < k; ++j)
      if (weight[j] > weight[i]) std::swap(weight[i], weight[j]), std::swap(rgb[i], rgb[j]);
  Vec3f sum{0, 0, 0};
  float total = 0;
  for (int i = 0; i < blend; ++i) {
    const float w = weight[i] * weight[i];
    sum = sum + rgb[i] * w;
    total += w;
  }
  out = sum * (1.f / total);
  return true;
}

Rgb8 toRgb8(Vec3f c) {
  auto byte = [](float x) { return uint8_t(std::clamp(x + 0.5f, 0.f, 255.f)); };
  return {byte(c.x), byte(c.y), byte(c.z), 255};
}

// Texels of one chart: each face's texels whose centre lies inside it (first pass), then those
// its edges graze (second pass, the point clamped onto the face), so that bilinear lookups at
// the chart's border find colour. `state`: 0 empty, 1 fallback colour, 2 colour from frames.
void bakeChart(const TriangleMesh& mesh, const UvAtlas& atlas, const std::vector<int32_t>& faces,
               const std::vector<BakeView>& views, const std::vector<FaceViews>& candidates, const BakeOptions& o,
               ColorImage& page, std::vector<uint8_t>& state) {
  const int P = atlas.page_px;
  for (int pass = 0; pass < 2; ++pass) {
    const float reach = pass == 0 ? 0.f : 0.75f;  // texels: a grazed texel's centre is this close to an edge
    for (int32_t f : faces) {
      const auto& c = atlas.corner_px[size_t(f)];
      const float area2 = (c[1].x - c[0].x) * (c[2].y - c[0].y) - (c[2].x - c[0].x) * (c[1].y - c[0].y);
      if (std::fabs(area2) < 1e-8f) continue;
      const int x0 = std::max(0, int(std::floor(std::min({c[0].x, c[1].x, c[2].x}) - reach))),
                x1 = std::min(P - 1, int(std::floor(std::max({c[0].x, c[1].x, c[2].x}) + reach))),
                y0 = std::max(0, int(std::floor(std::min({c[0].y, c[1].y, c[2].y}) - reach))),
                y1 = std::min(P - 1, int(std::floor(std::max({c[0].y, c[1].y, c[2].y}) + reach)));
      const auto& t = mesh.triangles[size_t(f)];
      const Vec3f A = mesh.positions[size_t(t[0])], B = mesh.positions[size_t(t[1])], C = mesh.positions[size_t(t[2])];
      const Vec3f n = faceNormal(mesh, size_t(f));
      // Edge lengths in texels, to turn barycentrics into distances from the edges.
      const float l0 = std::hypot(c[2].x - c[1].x, c[2].y - c[1].y), l1 = std::hypot(c[0].x - c[2].x, c[0].y - c[2].y),
                  l2 = std::hypot(c[1].x - c[0].x, c[1].y - c[0].y);
      for (int y = y0; y <= y1; ++y)
        for (int x = x0; x <= x1; ++x) {
          const size_t i = size_t(y) * size_t(P) + size_t(x);
          if (state[i] != 0) continue;
          const float px = float(x) + 0.5f, py = float(y) + 0.5f;
          float b0 = ((c[1].x - px) * (c[2].y - py) - (c[2].x - px) * (c[1].y - py)) / area2;
          float b1 = ((c[2].x - px) * (c[0].y - py) - (c[0].x - px) * (c[2].y - py)) / area2;
          float b2 = 1.f - b0 - b1;
          // Distance (texels) outside each edge: b_k * 2area / |edge_k| is the distance to edge k.
          const float d0 = b0 * std::fabs(area2) / std::max(l0, 1e-6f), d1 = b1 * std::fabs(area2) / std::max(l1, 1e-6f),
                      d2 = b2 * std::fabs(area2) / std::max(l2, 1e-6f);
          if (std::min({d0, d1, d2}) < -reach || (pass == 0 && std::min({d0, d1, d2}) < 0.f)) continue;
          b0 = std::max(b0, 0.f), b1 = std::max(b1, 0.f), b2 = std::max(b2, 0.f);
          const float s = b0 + b1 + b2;
          b0 /= s, b1 /= s, b2 /= s;
          const Vec3f p = A * b0 + B * b1 + C * b2;
          Vec3f rgb;
          if (blendTexel(views, candidates[size_t(f)], o, p, n, rgb)) {
            state[i] = 2;
          } else {
            const Rgb8 ca = mesh.colors[size_t(t[0])], cb = mesh.colors[size_t(t[1])], cc = mesh.colors[size_t(t[2])];
            rgb = {ca.r * b0 + cb.r * b1 + cc.r * b2, ca.g * b0 + cb.g * b1 + cc.g * b2, ca.b * b0 + cb.b * b1 + cc.b * b2};
            state[i] = 1;
          }
          page(x, y) = toRgb8(rgb);
        }
    }
  }
}

// Fills the empty texels of a chart's rectangle that touch coloured ones with their mean, ring
// by ring, so that the gutters carry the chart's border colours.
void dilateChart(const AtlasChart& chart, int rings, ColorImage& page, std::vector<uint8_t>& state) {
  const int P = page.width();
  for (int ring = 0; ring < rings; ++ring) {
    std::vector<std::pair<size_t, Rgb8>> fills;
    for (int y = chart.y; y < chart.y + chart.height; ++y)
      for (int x = chart.x; x < chart.x + chart.width; ++x) {
        if (state[size_t(y) * size_t(P) + size_t(x)] != 0) continue;
        int sum[3] = {0, 0, 0}, count = 0;
        for (int dy = -1; dy <= 1; ++dy)
          for (int dx = -1; dx <= 1; ++dx) {
            const int nx = x + dx, ny = y + dy;
            if (nx < chart.x || ny < chart.y || nx >= chart.x + chart.width || ny >= chart.y + chart.height) continue;
            if (state[size_t(ny) * size_t(P) + size_t(nx)] == 0) continue;
            const Rgb8 c = page(nx, ny);
            sum[0] += c.r, sum[1] += c.g, sum[2] += c.b, ++count;
          }
        if (count)
          fills.push_back({size_t(y) * size_t(P) + size_t(x),
                           Rgb8{uint8_t(sum[0] / count), uint8_t(sum[1] / count), uint8_t(sum[2] / count), 255}});
      }
    for (const auto& [i, c] : fills) {
      page.data()[i] = c;
      state[i] = 3;  // dilated
    }
  }
}

}  // namespace

ColorImage bakeTexture(const TriangleMesh& mesh, const UvAtlas& atlas, std::vector<BakeView> views,
                       const BakeOptions& o, BakeReport* report) {
  if (atlas.corner_px.size() != mesh.triangleCount()) throw Error("texture bake: the atlas was made for another mesh");
  if (!mesh.hasColors()) throw Error("texture bake: the mesh needs vertex colours (the fallback for unseen texels)");
  if (o.views_per_face < 1 || o.blend_views < 1) throw Error("texture bake: views per face and blend views must be >= 1");
  BakeReport r;
  auto t0 = std::chrono::steady_clock::now();
  const std::vector<FaceViews> candidates =
      shareWithNeighbours(selectViews(mesh, views, o, &r.faces_unseen), edgeNeighbours(mesh));
  if (o.equalise_exposure && views.size() > 1) equaliseExposure(mesh, candidates, views, o);
  for (const BakeView& v : views) r.gains.push_back(v.gain);
  r.select_s = secondsSince(t0);
  t0 = std::chrono::steady_clock::now();
  const int P = atlas.page_px;
  ColorImage page(P, P, Rgb8{0, 0, 0, 255});
  std::vector<uint8_t> state(size_t(P) * size_t(P), 0);
  // Faces of each chart (counting sort), charts baked in parallel: each owns its rectangle.
  std::vector<std::vector<int32_t>> chart_faces(atlas.charts.size());
  for (size_t f = 0; f < atlas.face_chart.size(); ++f) chart_faces[size_t(atlas.face_chart[f])].push_back(int32_t(f));
  std::atomic<size_t> faces_done{0};
  std::mutex progress_lock;
  tbb::parallel_for(tbb::blocked_range<size_t>(0, atlas.charts.size(), 1), [&](const tbb::blocked_range<size_t>& r) {
    for (size_t c = r.begin(); c != r.end(); ++c) {
      bakeChart(mesh, atlas, chart_faces[c], views, candidates, o, page, state);
      const size_t done = faces_done += chart_faces[c].size();
      if (o.on_progress && progress_lock.try_lock()) {
        o.on_progress(done, mesh.triangleCount());
        progress_lock.unlock();
      }
    }
  });
  r.bake_s = secondsSince(t0);
  t0 = std::chrono::steady_clock::now();
  for (uint8_t s : state) {
    r.from_frames += s == 2;
    r.from_fallback += s == 1;
  }
  r.texels = r.from_frames + r.from_fallback;
  tbb::parallel_for(tbb::blocked_range<size_t>(0, atlas.charts.size(), 16), [&](const tbb::blocked_range<size_t>& r) {
    for (size_t c = r.begin(); c != r.end(); ++c) dilateChart(atlas.charts[c], atlas.gutter_px + 1, page, state);
  });
  // Outside the charts: the mean colour, so that coarse mip levels fade towards it, not black.
  double sum[3] = {0, 0, 0};
  size_t count = 0;
  for (size_t i = 0; i < state.size(); ++i)
    if (state[i] == 2 || state[i] == 1) {
      const Rgb8 c = page.data()[i];
      sum[0] += c.r, sum[1] += c.g, sum[2] += c.b, ++count;
    }
  if (count) {
    const Rgb8 mean{uint8_t(sum[0] / double(count)), uint8_t(sum[1] / double(count)), uint8_t(sum[2] / double(count)), 255};
    for (size_t i = 0; i < state.size(); ++i)
      if (state[i] == 0) page.data()[i] = mean;
  }
  r.dilate_s = secondsSince(t0);
  if (report) *report = r;
  return page;
}

double imageSharpness(const ColorImage& color) {
  const int w = color.width() / 2, h = color.height() / 2;
  if (w < 3 || h < 3) return 0;
  std::vector<float> grey(size_t(w) * size_t(h));
  for (int y = 0; y < h; ++y)
    for (int x = 0; x < w; ++x) {
      float s = 0;
      for (int dy = 0; dy < 2; ++dy)
        for (int dx = 0; dx < 2; ++dx) {
          const Rgb8 c = color(2 * x + dx, 2 * y + dy);
          s += 0.299f * c.r + 0.587f * c.g + 0.114f * c.b;
        }
      grey[size_t(y) * size_t(w) + size_t(x)] = s * 0.25f;
    }
  double sum = 0, sum2 = 0;
  size_t n = 0;
  for (int y = 1; y < h - 1; ++y)
    for (int x = 1; x < w - 1; ++x) {
      const size_t i = size_t(y) * size_t(w) + size_t(x);
      const double lap = 4.0 * grey[i] - grey[i - 1] - grey[i + 1] - grey[i - size_t(w)] - grey[i + size_t(w)];
      sum += lap, sum2 += lap * lap, ++n;
    }
  const double mean = sum / double(n);
  return sum2 / double(n) - mean * mean;
}

}  // namespace vf
