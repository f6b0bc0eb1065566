// Charting (region growing with an overlap test in the chart's plane) and shelf packing.
#include "texture/uv_atlas.h"

#include <algorithm>
#include <cmath>
#include <numeric>
#include <unordered_map>

#include "core/error.h"

namespace vf {
namespace {

using Tri2 = std::array<Vec2f, 3>;

Vec3f faceNormalTimesTwoArea(const TriangleMesh& mesh, size_t f) {
  const auto& t = mesh.triangles[f];
  return cross(mesh.positions[size_t(t[1])] - mesh.positions[size_t(t[0])],
               mesh.positions[size_t(t[2])] - mesh.positions[size_t(t[0])]);
}

// Faces sharing an edge (at most the first two faces of each edge; a third is not a neighbour).
std::vector<std::array<int32_t, 3>> edgeNeighbours(const TriangleMesh& mesh) {
  std::vector<std::array<int32_t, 3>> nb(mesh.triangleCount(), {-1, -1, -1});
  std::unordered_map<uint64_t, std::pair<int32_t, int>> open;  // edge -> (face, corner) seen once
  open.reserve(mesh.triangleCount() * 2);
  for (size_t f = 0; f < mesh.triangleCount(); ++f) {
    for (int k = 0; k < 3; ++k) {
      const uint32_t a = uint32_t(mesh.triangles[f][size_t(k)]), b = uint32_t(mesh.triangles[f][size_t((k + 1) % 3)]);
      const uint64_t key = (uint64_t(std::min(a, b)) << 32) | std::max(a, b);
      auto [it, inserted] = open.emplace(key, std::make_pair(int32_t(f), k));
      if (inserted) continue;
      if (it->second.first >= 0) {
        nb[f][size_t(k)] = it->second.first;
        nb[size_t(it->second.first)][size_t(it->second.second)] = int32_t(f);
        it->second.first = -1;  // a third face on this edge stays apart
      }
    }
  }
  return nb;
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
  std::vector<int32_t> faces;
  float lo_x = 1e30f, lo_y = 1e30f, hi_x = -1e30f, hi_y = -1e30f;
};

// Grows charts from the largest faces first, so that walls and floors seed large planar charts.
std::vector<ChartBuild> growCharts(const TriangleMesh& mesh, const UvAtlasOptions& o, std::vector<Tri2>& flat) {
  const size_t n = mesh.triangleCount();
  std::vector<Vec3f> normal(n);
  std::vector<float> area(n);
  for (size_t f = 0; f < n; ++f) {
    const Vec3f c = faceNormalTimesTwoArea(mesh, f);
    area[f] = norm(c);
    normal[f] = area[f] > 0 ? c * (1.f / area[f]) : Vec3f{0, 0, 1};
  }
  const auto nb = edgeNeighbours(mesh);
  std::vector<int32_t> order(n);
  std::iota(order.begin(), order.end(), 0);
  std::stable_sort(order.begin(), order.end(), [&](int32_t a, int32_t b) { return area[size_t(a)] > area[size_t(b)]; });
  std::vector<int32_t> chart_of(n, -1);
  const float min_cos = std::cos(o.max_chart_angle_deg * float(M_PI) / 180.f);
  const float cell_m = std::max(0.02f, o.max_chart_m / 64.f);  // buckets of the overlap test
  std::vector<ChartBuild> charts;
  std::unordered_map<uint64_t, std::vector<int32_t>> buckets;
  std::vector<int32_t> queue, big;
  flat.assign(n, Tri2{});
  auto cellKey = [](int64_t x, int64_t y) { return (uint64_t(uint32_t(int32_t(x))) << 32) | uint32_t(int32_t(y)); };
  for (int32_t seed : order) {
    if (chart_of[size_t(seed)] >= 0) continue;
    ChartBuild c;
    c.axis = normal[size_t(seed)];
    planeBasis(c.axis, c.u, c.v);
    const int32_t id = int32_t(charts.size());
    buckets.clear();
    big.clear();
    queue.assign(1, seed);
    for (size_t head = 0; head < queue.size(); ++head) {
      const int32_t f = queue[head];
      if (chart_of[size_t(f)] >= 0) continue;
      if (f != seed && dot(normal[size_t(f)], c.axis) < min_cos) continue;
      Tri2 t;
      float lo_x = c.lo_x, lo_y = c.lo_y, hi_x = c.hi_x, hi_y = c.hi_y;
      for (int k = 0; k < 3; ++k) {
        const Vec3f p = mesh.positions[size_t(mesh.triangles[size_t(f)][size_t(k)])];
        t[size_t(k)] = {dot(p, c.u), dot(p, c.v)};
        lo_x = std::min(lo_x, t[size_t(k)].x), hi_x = std::max(hi_x, t[size_t(k)].x);
        lo_y = std::min(lo_y, t[size_t(k)].y), hi_y = std::max(hi_y, t[size_t(k)].y);
      }
      if (f != seed && (hi_x - lo_x > o.max_chart_m || hi_y - lo_y > o.max_chart_m)) continue;
      const int64_t x0 = int64_t(std::floor(std::min({t[0].x, t[1].x, t[2].x}) / cell_m)),
                    x1 = int64_t(std::floor(std::max({t[0].x, t[1].x, t[2].x}) / cell_m)),
                    y0 = int64_t(std::floor(std::min({t[0].y, t[1].y, t[2].y}) / cell_m)),
                    y1 = int64_t(std::floor(std::max({t[0].y, t[1].y, t[2].y}) / cell_m));
      bool overlap = false;
      for (int32_t g : big)
        if (interiorsOverlap(t, flat[size_t(g)])) overlap = true;
      for (int64_t x = x0; x <= x1 && !overlap; ++x)
        for (int64_t y = y0; y <= y1 && !overlap; ++y) {
          auto it = buckets.find(cellKey(x, y));
          if (it == buckets.end()) continue;
          for (int32_t g : it->second)
            if (interiorsOverlap(t, flat[size_t(g)])) {
              overlap = true;
              break;
            }
        }
      if (overlap) continue;  // left for a later chart
      // A face over many cells (a seed larger than a chart may be) is tested against every face.
      if ((x1 - x0 + 1) * (y1 - y0 + 1) > 4096) {
        big.push_back(f);
      } else {
        for (int64_t x = x0; x <= x1; ++x)
          for (int64_t y = y0; y <= y1; ++y) buckets[cellKey(x, y)].push_back(f);
      }
      flat[size_t(f)] = t;
      chart_of[size_t(f)] = id;
      c.faces.push_back(f);
      c.lo_x = lo_x, c.lo_y = lo_y, c.hi_x = hi_x, c.hi_y = hi_y;
      for (int32_t g : nb[size_t(f)])
        if (g >= 0 && chart_of[size_t(g)] < 0) queue.push_back(g);
    }
    charts.push_back(std::move(c));
  }
  return charts;
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
  const std::vector<ChartBuild> built = growCharts(mesh, o, flat);
  UvAtlas atlas;
  atlas.gutter_px = o.gutter_px;
  atlas.face_chart.resize(mesh.triangleCount());
  atlas.charts.resize(built.size());
  for (size_t c = 0; c < built.size(); ++c) {
    atlas.charts[c].axis = built[c].axis;
    atlas.charts[c].faces = int32_t(built[c].faces.size());
    for (int32_t f : built[c].faces) atlas.face_chart[size_t(f)] = int32_t(c);
  }
  // Texel size and page: the smallest power of two that the charts' area could fill, doubled
  // until the shelves fit, then coarser texels once the largest page is reached.
  float texel = o.texel_m;
  for (;;) {
    double area = 0;
    for (size_t c = 0; c < built.size(); ++c) {
      AtlasChart& a = atlas.charts[c];
      a.width = int(std::ceil((built[c].hi_x - built[c].lo_x) / texel)) + 1 + 2 * o.gutter_px;
      a.height = int(std::ceil((built[c].hi_y - built[c].lo_y) / texel)) + 1 + 2 * o.gutter_px;
      area += double(a.width) * a.height;
    }
    int page = 16;
    while (page < o.max_page_px && double(page) * page < area) page *= 2;
    while (!packShelves(atlas.charts, page) && page < o.max_page_px) page *= 2;
    if (packShelves(atlas.charts, page)) {
      atlas.page_px = page;
      break;
    }
    texel *= 1.15f;
    if (texel > 1.f) throw Error("UV atlas: the charts do not fit a " + std::to_string(o.max_page_px) + " px page");
  }
  atlas.texel_m = texel;
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
