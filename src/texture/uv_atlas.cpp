// Charting (region growing with an overlap test in the chart's plane) and shelf packing.
#include "texture/uv_atlas.h"

#include <algorithm>
#include <cmath>
#include <numeric>
#include <unordered_map>

#include "core/error.h"
#include "texture/mesh_adjacency.h"

namespace vf {
namespace {

using Tri2 = std::array<Vec2f, 3>;

Vec3f faceNormalTimesTwoArea(const TriangleMesh& mesh, size_t f) {
  const auto& t = mesh.triangles[f];
  return cross(mesh.positions[size_t(t[1])] - mesh.positions[size_t(t[0])],
               mesh.positions[size_t(t[2])] - mesh.positions[size_t(t[0])]);
}

// Whether two triangles' interiors overlap in the plane (separating axes; touching is not overlap).
bool interiorsOverlap(const Tri2& a, const Tri2& b) {
  constexpr double kTouch = 1e-7;  // metres: shared edges and vertices touch within rounding
  for (const Tri2* t : {&a, &b}) {
    for (int k = 0; k < 3; ++k) {
      const Vec2f p = (*t)[size_t(k)], q = (*t)[size_t((k + 1) % 3)];
      const double nx = -(double(q.y) - p.y), ny = double(q.x) - p.x;
      const double len = std::sqrt(nx * nx + ny * ny);
      if (len < 1e-12) continue;
      double a_lo = 1e300, a_hi = -1e300, b_lo = 1e300, b_hi = -1e300;
      for (const Vec2f& v : a) {
        const double d = (nx * v.x + ny * v.y) / len;
        a_lo = std::min(a_lo, d), a_hi = std::max(a_hi, d);
      }
      for (const Vec2f& v : b) {
        const double d = (nx * v.x + ny * v.y) / len;
        b_lo = std::min(b_lo, d), b_hi = std::max(b_hi, d);
      }
      if (a_hi <= b_lo + kTouch || b_hi <= a_lo + kTouch) return false;
    }
  }
  return true;
}

// Any two unit vectors across `axis`, making a right-handed frame (u, v, axis).
void planeBasis(Vec3f axis, Vec3f& u, Vec3f& v) {
  const Vec3f helper = std::fabs(axis.z) < 0.9f ? Vec3f{0, 0, 1} : Vec3f{1, 0, 0};
  u = normalized(cross(helper, axis));
  v = cross(axis, u);
}

struct ChartBuild {
  Vec3f axis, u, v;
  std::vector<int32_t> faces, huge_faces;
  float lo_x = 1e30f, lo_y = 1e30f, hi_x = -1e30f, hi_y = -1e30f;
};

// Charts grown face by face: a face joins a chart when it leans no more than the limit from the
// chart's axis, keeps the chart within max_chart_m, and overlaps none of its faces in the plane
// (separating axes against the chart's faces in nearby cells of a grid over the plane).
class ChartGrower {
 public:
  ChartGrower(const TriangleMesh& mesh, const UvAtlasOptions& o) : mesh_(mesh), o_(o) {
    const size_t n = mesh.triangleCount();
    normal_.resize(n);
    area2_.resize(n);
    for (size_t f = 0; f < n; ++f) {
      const Vec3f c = faceNormalTimesTwoArea(mesh, f);
      area2_[f] = norm(c);
      normal_[f] = area2_[f] > 0 ? c * (1.f / area2_[f]) : Vec3f{0, 0, 1};
    }
    chart_of_.assign(n, -1);
    flat_.assign(n, Tri2{});
    cell_m_ = std::max(0.02f, o.max_chart_m / 64.f);
  }

  const Vec3f& normal(size_t f) const { return normal_[f]; }
  float area2(size_t f) const { return area2_[f]; }
  int32_t chartOf(size_t f) const { return chart_of_[f]; }
  std::vector<ChartBuild>& charts() { return charts_; }
  std::vector<Tri2>& flat() { return flat_; }

  int32_t newChart(Vec3f axis) {
    ChartBuild c;
    c.axis = axis;
    planeBasis(axis, c.u, c.v);
    charts_.push_back(std::move(c));
    return int32_t(charts_.size() - 1);
  }

  // Adds face f to chart `id` when it may join (always when the chart is empty).
  bool tryAdd(int32_t f, int32_t id, float min_cos) {
    ChartBuild& c = charts_[size_t(id)];
    const bool first = c.faces.empty();
    // A sliver (under a texel of area) carries no colour of its own: its normal, unreliable
    // anyway, does not keep it out; the overlap test still does.
    const bool sliver = area2_[size_t(f)] < 2.f * o_.texel_m * o_.texel_m;
    if (!first && !sliver && dot(normal_[size_t(f)], c.axis) < min_cos) return false;
    Tri2 t;
    float lo_x = c.lo_x, lo_y = c.lo_y, hi_x = c.hi_x, hi_y = c.hi_y;
    for (int k = 0; k < 3; ++k) {
      const Vec3f p = mesh_.positions[size_t(mesh_.triangles[size_t(f)][size_t(k)])];
      t[size_t(k)] = {dot(p, c.u), dot(p, c.v)};
      lo_x = std::min(lo_x, t[size_t(k)].x), hi_x = std::max(hi_x, t[size_t(k)].x);
      lo_y = std::min(lo_y, t[size_t(k)].y), hi_y = std::max(hi_y, t[size_t(k)].y);
    }
    if (!first && (hi_x - lo_x > o_.max_chart_m || hi_y - lo_y > o_.max_chart_m)) return false;
    const int64_t x0 = cell(std::min({t[0].x, t[1].x, t[2].x})), x1 = cell(std::max({t[0].x, t[1].x, t[2].x})),
                  y0 = cell(std::min({t[0].y, t[1].y, t[2].y})), y1 = cell(std::max({t[0].y, t[1].y, t[2].y}));
    // A face over many cells (a seed larger than a chart may be) is tested against every face.
    const bool huge = (x1 - x0 + 1) * (y1 - y0 + 1) > 4096;
    if (!first) {
      for (int32_t g : c.huge_faces)
        if (interiorsOverlap(t, flat_[size_t(g)])) return false;
      if (huge) {
        for (int32_t g : c.faces)
          if (interiorsOverlap(t, flat_[size_t(g)])) return false;
      } else {
        for (int64_t x = x0; x <= x1; ++x)
          for (int64_t y = y0; y <= y1; ++y) {
            auto it = buckets_.find(key(id, x, y));
            if (it == buckets_.end()) continue;
            for (int32_t g : it->second)
              if (interiorsOverlap(t, flat_[size_t(g)])) return false;
          }
      }
    }
    if (huge) {
      c.huge_faces.push_back(f);
    } else {
      for (int64_t x = x0; x <= x1; ++x)
        for (int64_t y = y0; y <= y1; ++y) buckets_[key(id, x, y)].push_back(f);
    }
    flat_[size_t(f)] = t;
    chart_of_[size_t(f)] = id;
    c.faces.push_back(f);
    c.lo_x = lo_x, c.lo_y = lo_y, c.hi_x = hi_x, c.hi_y = hi_y;
    return true;
  }

  // Takes face f out of its chart (the chart's extent is left as it was: a little slack).
  void remove(int32_t f) {
    ChartBuild& c = charts_[size_t(chart_of_[size_t(f)])];
    c.faces.erase(std::find(c.faces.begin(), c.faces.end(), f));
    auto h = std::find(c.huge_faces.begin(), c.huge_faces.end(), f);
    if (h != c.huge_faces.end()) c.huge_faces.erase(h);
    const Tri2& t = flat_[size_t(f)];
    for (int64_t x = cell(std::min({t[0].x, t[1].x, t[2].x})); x <= cell(std::max({t[0].x, t[1].x, t[2].x})); ++x)
      for (int64_t y = cell(std::min({t[0].y, t[1].y, t[2].y})); y <= cell(std::max({t[0].y, t[1].y, t[2].y})); ++y) {
        auto it = buckets_.find(key(chart_of_[size_t(f)], x, y));
        if (it != buckets_.end()) it->second.erase(std::remove(it->second.begin(), it->second.end(), f), it->second.end());
      }
    chart_of_[size_t(f)] = -1;
  }

 private:
  int64_t cell(float v) const { return int64_t(std::floor(v / cell_m_)); }
  // Chart (24 bits) and cell (20 bits each, wrapping: a collision only costs a test).
  static uint64_t key(int32_t chart, int64_t x, int64_t y) {
    return (uint64_t(uint32_t(chart)) << 40) | ((uint64_t(x) & 0xFFFFF) << 20) | (uint64_t(y) & 0xFFFFF);
  }

  const TriangleMesh& mesh_;
  const UvAtlasOptions& o_;
  std::vector<Vec3f> normal_;
  std::vector<float> area2_;
  std::vector<int32_t> chart_of_;
  std::vector<Tri2> flat_;
  std::vector<ChartBuild> charts_;
  std::unordered_map<uint64_t, std::vector<int32_t>> buckets_;
  float cell_m_ = 0.02f;
};

// Grows charts from the largest faces first, so that walls and floors seed large planar charts;
// then moves the faces of tiny charts (what was left between larger ones: noise, creases) into
// a neighbouring chart whose plane they do not flip in: each tiny chart costs a seam and a
// gutter all round, several times its own texels.
std::vector<ChartBuild> growCharts(const TriangleMesh& mesh, const UvAtlasOptions& o, std::vector<Tri2>& flat) {
  const size_t n = mesh.triangleCount();
  ChartGrower grower(mesh, o);
  const auto nb = edgeNeighbours(mesh);
  std::vector<int32_t> order(n);
  std::iota(order.begin(), order.end(), 0);
  std::stable_sort(order.begin(), order.end(),
                   [&](int32_t a, int32_t b) { return grower.area2(size_t(a)) > grower.area2(size_t(b)); });
  const float min_cos = std::cos(o.max_chart_angle_deg * float(M_PI) / 180.f);
  // Each seed not yet charted starts a chart that grows breadth-first over edge neighbours
  // whose normal keeps a cosine of at least `cos_limit` with the seed's.
  std::vector<int32_t> queue;
  auto growFromSeeds = [&](const std::vector<int32_t>& seeds, float cos_limit) {
    for (int32_t seed : seeds) {
      if (grower.chartOf(size_t(seed)) >= 0) continue;
      const int32_t id = grower.newChart(grower.normal(size_t(seed)));
      queue.assign(1, seed);
      for (size_t head = 0; head < queue.size(); ++head) {
        const int32_t f = queue[head];
        if (grower.chartOf(size_t(f)) >= 0 || !grower.tryAdd(f, id, cos_limit)) continue;
        for (int32_t g : nb[size_t(f)])
          if (g >= 0 && grower.chartOf(size_t(g)) < 0) queue.push_back(g);
      }
    }
  };
  growFromSeeds(order, min_cos);
  // Faces of tiny charts are released, offered to a neighbouring larger chart at a relaxed
  // angle, and what none takes is charted again among itself at that angle.
  constexpr size_t kTiny = 4;        // faces
  const float relaxed_cos = 0.2f;    // 78 degrees: stretched, but never flipped
  std::vector<int32_t> released;
  for (size_t c = 0; c < grower.charts().size(); ++c)
    if (grower.charts()[c].faces.size() <= kTiny)
      for (int32_t f : std::vector<int32_t>(grower.charts()[c].faces)) {
        grower.remove(f);
        released.push_back(f);
      }
  std::stable_sort(released.begin(), released.end(),
                   [&](int32_t a, int32_t b) { return grower.area2(size_t(a)) > grower.area2(size_t(b)); });
  for (int32_t f : released)
    for (int32_t g : nb[size_t(f)]) {
      if (grower.chartOf(size_t(f)) >= 0) break;
      const int32_t target = g < 0 ? -1 : grower.chartOf(size_t(g));
      if (target >= 0) grower.tryAdd(f, target, relaxed_cos);
    }
  growFromSeeds(released, relaxed_cos);
  std::vector<ChartBuild> charts;
  for (ChartBuild& c : grower.charts())
    if (!c.faces.empty()) charts.push_back(std::move(c));
  flat = std::move(grower.flat());
  return charts;
}

// Turns a chart in its plane to the angle whose bounding box is smallest, among the directions
// of its faces' edges (all of them for small charts, the largest face's otherwise) and its
// principal axis: a lone triangle then lies on its longest side, a wall along its length.
void turnToSmallestBox(ChartBuild& c, std::vector<Tri2>& flat) {
  std::vector<float> angles;
  int32_t largest = c.faces[0];
  float largest_area = -1;
  double sx = 0, sy = 0, sxx = 0, syy = 0, sxy = 0, count = 0;
  for (int32_t f : c.faces) {
    const Tri2& t = flat[size_t(f)];
    const float a = std::fabs((t[1].x - t[0].x) * (t[2].y - t[0].y) - (t[2].x - t[0].x) * (t[1].y - t[0].y));
    if (a > largest_area) largest_area = a, largest = f;
    for (const Vec2f& p : t) sx += p.x, sy += p.y, sxx += double(p.x) * p.x, syy += double(p.y) * p.y, sxy += double(p.x) * p.y, ++count;
  }
  auto addEdges = [&](int32_t f) {
    const Tri2& t = flat[size_t(f)];
    for (int k = 0; k < 3; ++k)
      angles.push_back(std::atan2(t[size_t((k + 1) % 3)].y - t[size_t(k)].y, t[size_t((k + 1) % 3)].x - t[size_t(k)].x));
  };
  if (c.faces.size() <= 16)
    for (int32_t f : c.faces) addEdges(f);
  else
    addEdges(largest);
  const double mx = sx / count, my = sy / count;
  angles.push_back(0.5f * float(std::atan2(2 * (sxy / count - mx * my), (sxx / count - mx * mx) - (syy / count - my * my))));
  float best_angle = 0, best_area = 1e30f;
  for (float a : angles) {
    const float ca = std::cos(a), sa = std::sin(a);
    float lo_x = 1e30f, lo_y = 1e30f, hi_x = -1e30f, hi_y = -1e30f;
    for (int32_t f : c.faces)
      for (const Vec2f& p : flat[size_t(f)]) {
        const float x = ca * p.x + sa * p.y, y = -sa * p.x + ca * p.y;
        lo_x = std::min(lo_x, x), hi_x = std::max(hi_x, x), lo_y = std::min(lo_y, y), hi_y = std::max(hi_y, y);
      }
    const float area = (hi_x - lo_x) * (hi_y - lo_y);
    if (area < best_area) best_area = area, best_angle = a;
  }
  const float ca = std::cos(best_angle), sa = std::sin(best_angle);
  c.lo_x = c.lo_y = 1e30f, c.hi_x = c.hi_y = -1e30f;
  for (int32_t f : c.faces)
    for (Vec2f& p : flat[size_t(f)]) {
      p = {ca * p.x + sa * p.y, -sa * p.x + ca * p.y};  // a rotation: orientation and overlaps unchanged
      c.lo_x = std::min(c.lo_x, p.x), c.hi_x = std::max(c.hi_x, p.x), c.lo_y = std::min(c.lo_y, p.y), c.hi_y = std::max(c.hi_y, p.y);
    }
}

// Shelf packing, tallest first, into a square page; false when the page is too small.
bool packShelves(std::vector<AtlasChart>& charts, int page_px) {
  std::vector<size_t> order(charts.size());
  std::iota(order.begin(), order.end(), size_t(0));
  std::stable_sort(order.begin(), order.end(), [&](size_t a, size_t b) { return charts[a].height > charts[b].height; });
  int x = 0, y = 0, shelf = 0;
  for (size_t i : order) {
    AtlasChart& c = charts[i];
    if (c.width > page_px) return false;
    if (x + c.width > page_px) y += shelf, x = 0, shelf = 0;
    if (y + c.height > page_px) return false;
    c.x = x, c.y = y;
    x += c.width;
    shelf = std::max(shelf, c.height);
  }
  return true;
}

}  // namespace

UvAtlas buildUvAtlas(const TriangleMesh& mesh, const UvAtlasOptions& o) {
  if (!(o.texel_m > 0) || !(o.max_chart_m > 0) || o.gutter_px < 0 || o.max_page_px < 16 ||
      (o.max_page_px & (o.max_page_px - 1)) != 0 || !(o.max_chart_angle_deg > 0 && o.max_chart_angle_deg < 90))
    throw Error("UV atlas: invalid options (texel > 0, page a power of two >= 16, gutter >= 0, angle in (0, 90))");
  if (mesh.triangles.empty()) throw Error("UV atlas: the mesh has no triangles");
  std::vector<Tri2> flat;
  std::vector<ChartBuild> built = growCharts(mesh, o, flat);
  for (ChartBuild& c : built) turnToSmallestBox(c, flat);
  UvAtlas atlas;
  atlas.gutter_px = o.gutter_px;
  atlas.face_chart.resize(mesh.triangleCount());
  atlas.charts.resize(built.size());
  for (size_t c = 0; c < built.size(); ++c) {
    atlas.charts[c].axis = built[c].axis;
    atlas.charts[c].faces = int32_t(built[c].faces.size());
    for (int32_t f : built[c].faces) atlas.face_chart[size_t(f)] = int32_t(c);
  }
  // Texel size and page: the smallest page (a power of two) that holds the charts at texels at
  // most a quarter coarser than asked (a page 4 times larger for 25 % finer texels would be
  // mostly gutter and shelf waste), else the largest page at whatever texel fits.
  auto sizeCharts = [&](float texel) {
    double area = 0;
    for (size_t c = 0; c < built.size(); ++c) {
      AtlasChart& a = atlas.charts[c];
      a.width = int(std::ceil((built[c].hi_x - built[c].lo_x) / texel)) + 1 + 2 * o.gutter_px;
      a.height = int(std::ceil((built[c].hi_y - built[c].lo_y) / texel)) + 1 + 2 * o.gutter_px;
      area += double(a.width) * a.height;
    }
    return area;
  };
  atlas.page_px = 0;
  for (int page = 16; page <= o.max_page_px && !atlas.page_px; page *= 2) {
    const float coarsest = page == o.max_page_px ? 1.f : 1.25f * o.texel_m;
    for (float texel = o.texel_m; texel <= coarsest; texel *= 1.05f) {
      if (sizeCharts(texel) > double(page) * page) continue;  // cannot fit: coarser
      if (packShelves(atlas.charts, page)) {
        atlas.page_px = page;
        atlas.texel_m = texel;
        break;
      }
    }
  }
  if (!atlas.page_px) throw Error("UV atlas: the charts do not fit a " + std::to_string(o.max_page_px) + " px page");
  const float texel = atlas.texel_m;
  atlas.corner_px.resize(mesh.triangleCount());
  for (size_t c = 0; c < built.size(); ++c) {
    const AtlasChart& a = atlas.charts[c];
    // Chart point (lo_x, lo_y) lands on the centre of the first texel inside the gutter.
    const float ox = float(a.x + o.gutter_px) + 0.5f, oy = float(a.y + o.gutter_px) + 0.5f;
    for (int32_t f : built[c].faces)
      for (int k = 0; k < 3; ++k) {
        const Vec2f p = flat[size_t(f)][size_t(k)];
        atlas.corner_px[size_t(f)][size_t(k)] = {ox + (p.x - built[c].lo_x) / texel, oy + (p.y - built[c].lo_y) / texel};
      }
  }
  return atlas;
}

TriangleMesh applyAtlas(const TriangleMesh& mesh, const UvAtlas& atlas) {
  if (atlas.face_chart.size() != mesh.triangleCount()) throw Error("UV atlas: made for another mesh");
  TriangleMesh out;
  out.triangles.resize(mesh.triangleCount());
  // One output vertex per (vertex, chart): a vertex has one position in each chart it is in.
  std::unordered_map<uint64_t, int32_t> index;
  index.reserve(mesh.vertexCount() * 2);
  const float page = float(atlas.page_px);
  for (size_t f = 0; f < mesh.triangleCount(); ++f) {
    for (int k = 0; k < 3; ++k) {
      const int32_t v = mesh.triangles[f][size_t(k)];
      const uint64_t key = (uint64_t(uint32_t(atlas.face_chart[f])) << 32) | uint32_t(v);
      auto [it, inserted] = index.emplace(key, int32_t(out.positions.size()));
      if (inserted) {
        out.positions.push_back(mesh.positions[size_t(v)]);
        if (mesh.hasNormals()) out.normals.push_back(mesh.normals[size_t(v)]);
        if (mesh.hasColors()) out.colors.push_back(mesh.colors[size_t(v)]);
        if (mesh.hasClasses()) out.classes.push_back(mesh.classes[size_t(v)]);
        const Vec2f px = atlas.corner_px[f][size_t(k)];
        out.uvs.push_back({px.x / page, 1.f - px.y / page});
      }
      out.triangles[f][size_t(k)] = it->second;
    }
  }
  return out;
}

}  // namespace vf
