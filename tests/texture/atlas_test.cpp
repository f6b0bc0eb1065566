// Simplification and the UV atlas on a real fused surface (TUM fr1/xyz, 20 frames): the
// simplified mesh stays within millimetres of the full one, and the atlas's pages are powers of
// two with charts that never share a texel, 2 free texels at least between any two, and no
// two faces of one chart covering the same texel.
#include <gtest/gtest.h>

#include <algorithm>

#include "fusion/pipeline.h"
#include "io/mesh_metrics.h"
#include "io/triangle_bvh.h"
#include "io/tum_dataset.h"
#include "test_data.h"
#include "texture/mesh_simplify.h"
#include "texture/uv_atlas.h"
#include "vdb/mesher.h"
#include "vdb/scene.h"

namespace vf {
namespace {

TriangleMesh fusedTumMesh() {
  const std::string folder = test::dataPath("tum_fr1_xyz_head100");
  const TumDataset source(folder);
  PipelineParams params;
  params.volume.voxel_size_m = 3.f / 512;
  Pipeline pipeline(params, source.depthIntrinsics(), Device::Cpu);
  for (int i = 0; i < 100; i += 5) pipeline.processFrame(source.load(i));
  return meshScene(sceneFromBricks(pipeline.hostVolume(), {}));
}

const TriangleMesh& fullMesh() {
  static const TriangleMesh mesh = fusedTumMesh();
  return mesh;
}

float percentile(std::vector<float> v, double q) {
  std::nth_element(v.begin(), v.begin() + long(q * double(v.size() - 1)), v.end());
  return v[size_t(q * double(v.size() - 1))];
}

TEST(Simplification, AnEighthOfTheTrianglesStaysWithinFiveMillimetresOfTheFullSurface) {
  VF_REQUIRE_DATA(folder, "tum_fr1_xyz_head100");
  const TriangleMesh& full = fullMesh();
  ASSERT_GT(full.triangleCount(), 200000u);
  SimplifyOptions o;
  o.target_triangles = full.triangleCount() / 8;
  SimplifyReport report;
  const TriangleMesh simple = simplifyMesh(full, o, &report);
  EXPECT_LE(simple.triangleCount(), o.target_triangles);
  EXPECT_EQ(simple.colors.size(), simple.positions.size());
  // Both ways: full-surface points to the simplified surface, and back.
  const std::vector<float> to_simple = TriangleBvh(simple).distances(sampleSurface(full, 200000));
  const std::vector<float> to_full = TriangleBvh(full).distances(sampleSurface(simple, 200000));
  const float p90_a = percentile(to_simple, 0.9), p90_b = percentile(to_full, 0.9);
  std::printf("%zu -> %zu triangles: p90 full->simplified %.2f mm, simplified->full %.2f mm, max reported %.1f mm\n",
              full.triangleCount(), simple.triangleCount(), p90_a * 1000, p90_b * 1000, report.error_m * 1000);
  EXPECT_LT(p90_a, 0.005f);
  EXPECT_LT(p90_b, 0.005f);
}

// Texels a face touches: those whose square the triangle (corners in texels) reaches, tested
// as centres within half a diagonal of it.
template <class F>
void forTouchedTexels(const std::array<Vec2f, 3>& c, float reach, F&& f) {
  const float area2 = (c[1].x - c[0].x) * (c[2].y - c[0].y) - (c[2].x - c[0].x) * (c[1].y - c[0].y);
  if (std::fabs(area2) < 1e-9f) return;
  const int x0 = int(std::floor(std::min({c[0].x, c[1].x, c[2].x}) - 1)), x1 = int(std::max({c[0].x, c[1].x, c[2].x}) + 1);
  const int y0 = int(std::floor(std::min({c[0].y, c[1].y, c[2].y}) - 1)), y1 = int(std::max({c[0].y, c[1].y, c[2].y}) + 1);
  for (int y = y0; y <= y1; ++y)
    for (int x = x0; x <= x1; ++x) {
      const float px = float(x) + 0.5f, py = float(y) + 0.5f;
      float inside = 1e30f;  // signed distance inside the triangle (texels)
      for (int k = 0; k < 3; ++k) {
        const Vec2f a = c[size_t(k)], b = c[size_t((k + 1) % 3)];
        const float len = std::hypot(b.x - a.x, b.y - a.y);
        const float d = ((b.x - a.x) * (py - a.y) - (b.y - a.y) * (px - a.x)) / std::max(len, 1e-9f);
        inside = std::min(inside, area2 > 0 ? d : -d);
      }
      if (inside >= -reach) f(x, y);
    }
}

TEST(UvAtlas, ChartsNeverShareATexelAndKeepTwoFreeTexelsBetweenThem) {
  VF_REQUIRE_DATA(folder, "tum_fr1_xyz_head100");
  SimplifyOptions so;
  so.target_triangles = 150000;
  const TriangleMesh mesh = simplifyMesh(fullMesh(), so);
  UvAtlasOptions o;
  o.texel_m = 0.002f;
  const UvAtlas atlas = buildUvAtlas(mesh, o);
  const int P = atlas.page_px;
  EXPECT_TRUE(P >= 16 && P <= 8192 && (P & (P - 1)) == 0) << P;
  EXPECT_GE(atlas.gutter_px, 2);
  std::printf("%zu faces: %zu charts on %d x %d, texel %.2f mm\n", mesh.triangleCount(), atlas.charts.size(), P, P,
              atlas.texel_m * 1000);
  std::vector<int32_t> chart_at(size_t(P) * size_t(P), -1), face_at(size_t(P) * size_t(P), -1);
  size_t outside = 0, shared = 0, folded = 0;
  for (size_t f = 0; f < mesh.triangleCount(); ++f) {
    const int32_t chart = atlas.face_chart[f];
    const AtlasChart& rect = atlas.charts[size_t(chart)];
    forTouchedTexels(atlas.corner_px[f], 0.7072f, [&](int x, int y) {
      if (x < rect.x || y < rect.y || x >= rect.x + rect.width || y >= rect.y + rect.height) return void(++outside);
      int32_t& owner = chart_at[size_t(y) * size_t(P) + size_t(x)];
      if (owner >= 0 && owner != chart) ++shared;
      owner = chart;
    });
    // Centres well inside a face: another face of the chart covering one means the chart folds.
    forTouchedTexels(atlas.corner_px[f], -0.01f, [&](int x, int y) {
      int32_t& owner = face_at[size_t(y) * size_t(P) + size_t(x)];
      if (owner >= 0 && owner != int32_t(f)) ++folded;
      owner = int32_t(f);
    });
  }
  EXPECT_EQ(outside, 0u) << "texels outside their chart's rectangle";
  EXPECT_EQ(shared, 0u) << "texels two charts touch";
  EXPECT_EQ(folded, 0u) << "texel centres inside two faces";
  // Two free texels between charts: nothing of another chart within two texels (Chebyshev).
  size_t close = 0;
  for (int y = 0; y < P; ++y)
    for (int x = 0; x < P; ++x) {
      const int32_t c = chart_at[size_t(y) * size_t(P) + size_t(x)];
      if (c < 0) continue;
      for (int dy = -2; dy <= 2; ++dy)
        for (int dx = -2; dx <= 2; ++dx) {
          const int nx = x + dx, ny = y + dy;
          if (nx < 0 || ny < 0 || nx >= P || ny >= P) continue;
          const int32_t d = chart_at[size_t(ny) * size_t(P) + size_t(nx)];
          close += d >= 0 && d != c;
        }
    }
  EXPECT_EQ(close, 0u);
  // The atlas uses its page: the page half as wide could not hold the charts (their rectangles
  // fill over a quarter of this one: 36.7 %), and the faces touch 37.8 % of the texels of their
  // charts' rectangles (gutters and the charts' own shapes take the rest). What the faces touch
  // of the whole page follows the mesh's area: 13.9 % here, 19.7 % on the mesh that also fused
  // frame 90 6.5 cm off (before IcpParams::min_covered_match rejected it).
  size_t used = 0;
  for (int32_t c : chart_at) used += c >= 0;
  double rects = 0;
  for (const AtlasChart& c : atlas.charts) rects += double(c.width) * c.height;
  EXPECT_GT(rects / (double(P) * P), 0.25);
  EXPECT_GT(double(used) / rects, 0.3);
  // applyAtlas: uvs in [0, 1], faces unchanged in number.
  const TriangleMesh textured = applyAtlas(mesh, atlas);
  EXPECT_EQ(textured.triangleCount(), mesh.triangleCount());
  for (const Vec2f& uv : textured.uvs) ASSERT_TRUE(uv.x > 0 && uv.x < 1 && uv.y > 0 && uv.y < 1);
}

}  // namespace
}  // namespace vf
