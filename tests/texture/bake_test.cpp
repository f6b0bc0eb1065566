// The bake's rules on a scene whose right answer is known: a 1 m square wall 1.5 m in front of
// a camera, its colour image uniform. Every texel the frame sees takes the frame's colour; a
// texel behind an occluder (nearer depth) or under a masked pixel never does; texels no frame
// sees take the vertex colours; and the gutters carry the charts' colours.
#include <gtest/gtest.h>

#include "texture/texture_bake.h"
#include "texture/uv_atlas.h"

namespace vf {
namespace {

constexpr Rgb8 kWallVertexColour{0, 0, 255, 255};  // the fallback: blue
constexpr Rgb8 kFrameColour{0, 200, 0, 255};       // what the camera sees: green

// A square wall in the plane z = 1.5 m, x and y in [-0.5, 0.5], facing the camera at the
// origin (normals towards -z), as an n x n grid of quads.
TriangleMesh wall(int n) {
  TriangleMesh m;
  for (int j = 0; j <= n; ++j)
    for (int i = 0; i <= n; ++i) {
      m.positions.push_back({-0.5f + float(i) / float(n), -0.5f + float(j) / float(n), 1.5f});
      m.colors.push_back(kWallVertexColour);
    }
  for (int j = 0; j < n; ++j)
    for (int i = 0; i < n; ++i) {
      const int a = j * (n + 1) + i, b = a + 1, c = a + n + 1, d = c + 1;
      // Counter-clockwise seen from the camera (from -z): normal (0, 0, -1).
      m.triangles.push_back({a, c, b});
      m.triangles.push_back({b, c, d});
    }
  return m;
}

struct Frame {
  ColorImage color;
  DepthImage depth;
  Image<uint8_t> mask;
  BakeView view;
};

// The camera at the origin looking down +z; 320x240, the wall filling its middle.
Frame frameOfWall() {
  Frame f;
  f.color = ColorImage(320, 240, kFrameColour);
  f.depth = DepthImage(320, 240, 1.5f);
  f.view.color_k = f.view.depth_k = {200.f, 200.f, 159.5f, 119.5f, 320, 240};
  return f;
}

void bind(Frame& f) {
  f.view.color = std::as_const(f.color).view();
  f.view.depth = std::as_const(f.depth).view();
  if (!f.mask.empty()) f.view.mask = std::as_const(f.mask).view();
}

struct Counts {
  size_t frame = 0, fallback = 0, other = 0;
};

// Texel colours inside the charts at world points x in [x0, x1] (the wall's left or right part).
Counts countWallTexels(const TriangleMesh& mesh, const UvAtlas& atlas, const ColorImage& page, float x0, float x1) {
  Counts c;
  for (size_t f = 0; f < mesh.triangleCount(); ++f) {
    const auto& t = mesh.triangles[f];
    const Vec3f centre = (mesh.positions[size_t(t[0])] + mesh.positions[size_t(t[1])] + mesh.positions[size_t(t[2])]) * (1.f / 3.f);
    if (centre.x < x0 || centre.x > x1) continue;
    const auto& px = atlas.corner_px[f];
    const int x = int((px[0].x + px[1].x + px[2].x) / 3.f), y = int((px[0].y + px[1].y + px[2].y) / 3.f);
    const Rgb8 v = page(x, y);
    if (v.g > 150 && v.b < 60) ++c.frame;
    else if (v.b > 200 && v.g < 60) ++c.fallback;
    else ++c.other;
  }
  return c;
}

TEST(TextureBake, TexelsTheFrameSeesTakeItsColourAndUnseenOnesTheVertexColours) {
  const TriangleMesh mesh = wall(40);
  UvAtlasOptions ao;
  ao.texel_m = 0.005f;
  const UvAtlas atlas = buildUvAtlas(mesh, ao);
  Frame f = frameOfWall();
  // Only the left half of the image has depth: the right half of the wall is unseen.
  for (int y = 0; y < 240; ++y)
    for (int x = 160; x < 320; ++x) f.depth(x, y) = 0.f;
  bind(f);
  BakeReport report;
  const ColorImage page = bakeTexture(mesh, atlas, {f.view}, BakeOptions{}, &report);
  const Counts left = countWallTexels(mesh, atlas, page, -0.5f, -0.05f);
  const Counts right = countWallTexels(mesh, atlas, page, 0.05f, 0.5f);
  EXPECT_EQ(left.frame, left.frame + left.fallback + left.other);
  EXPECT_EQ(right.fallback, right.frame + right.fallback + right.other);
  EXPECT_GT(left.frame, 1000u);
  EXPECT_NEAR(double(report.from_frames) / double(report.texels), 0.5, 0.05);
}

TEST(TextureBake, OccludedAndMaskedPixelsNeverPaint) {
  const TriangleMesh mesh = wall(40);
  UvAtlasOptions ao;
  ao.texel_m = 0.005f;
  const UvAtlas atlas = buildUvAtlas(mesh, ao);
  // Frame A: a person 1 m away covers the left half (nearer depth, red); frame B sees the whole
  // wall but its right half is masked (a person's label there), its pixels red too.
  Frame a = frameOfWall(), b = frameOfWall();
  for (int y = 0; y < 240; ++y)
    for (int x = 0; x < 140; ++x) a.depth(x, y) = 1.0f, a.color(x, y) = {255, 0, 0, 255};
  b.mask = Image<uint8_t>(320, 240, 0);
  for (int y = 0; y < 240; ++y)
    for (int x = 160; x < 320; ++x) b.mask(x, y) = 1, b.color(x, y) = {255, 0, 0, 255};
  bind(a);
  bind(b);
  const ColorImage page = bakeTexture(mesh, atlas, {a.view, b.view}, BakeOptions{}, nullptr);
  size_t red = 0, green = 0;
  for (size_t f = 0; f < mesh.triangleCount(); ++f) {
    const auto& px = atlas.corner_px[f];
    const Rgb8 v = page(int((px[0].x + px[1].x + px[2].x) / 3.f), int((px[0].y + px[1].y + px[2].y) / 3.f));
    red += v.r > 60;
    green += v.g > 150;
  }
  EXPECT_EQ(red, 0u) << "a person's pixels (occluding or masked) were painted onto the wall";
  EXPECT_GT(green, mesh.triangleCount() * 95 / 100) << "each half of the wall is seen unoccluded by one frame";
}

TEST(TextureBake, GuttersCarryTheChartColour) {
  const TriangleMesh mesh = wall(8);
  UvAtlasOptions ao;
  ao.texel_m = 0.01f;
  const UvAtlas atlas = buildUvAtlas(mesh, ao);
  Frame f = frameOfWall();
  bind(f);
  const ColorImage page = bakeTexture(mesh, atlas, {f.view}, BakeOptions{}, nullptr);
  ASSERT_EQ(atlas.charts.size(), 1u);
  const AtlasChart& c = atlas.charts[0];
  // Every texel of the chart's rectangle, its 2-texel gutter included, is the frame's green.
  size_t green = 0, total = 0;
  for (int y = c.y; y < c.y + c.height; ++y)
    for (int x = c.x; x < c.x + c.width; ++x, ++total) green += page(x, y).g > 150 && page(x, y).b < 60;
  EXPECT_EQ(green, total);
}

}  // namespace
}  // namespace vf
