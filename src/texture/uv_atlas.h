#pragma once
// A UV atlas for a scanned mesh: charts of connected faces that face one way, each flattened by
// an orthographic projection onto the plane across its seed face's normal (faces within
// max_chart_angle_deg of it, so no face flips), grown only while no face overlaps another in the
// plane, then packed on shelves into one power-of-two texture page with gutters around each
// chart, so that bilinear filtering and the first mip levels never mix two charts.
#include <array>
#include <cstdint>
#include <vector>

#include "core/mesh.h"

namespace vf {

struct UvAtlasOptions {
  float texel_m = 0.0025f;          // wanted texel size; grown when the charts do not fit a page
  int max_page_px = 8192;           // the largest page (a power of two)
  int gutter_px = 2;                // free texels around every chart (4 between two charts)
  float max_chart_m = 2.f;          // a chart's largest extent in its plane
  float max_chart_angle_deg = 45.f; // between a face's normal and its chart's axis
};

struct AtlasChart {
  int x = 0, y = 0, width = 0, height = 0;  // the chart's rectangle in the page (texels), gutters included
  Vec3f axis{0, 0, 1};                      // the projection direction (the seed face's normal)
  int32_t faces = 0;
};

struct UvAtlas {
  int page_px = 0;       // the page is page_px x page_px texels
  float texel_m = 0;     // the texel size the charts were packed at
  int gutter_px = 0;
  std::vector<AtlasChart> charts;
  std::vector<int32_t> face_chart;               // per face
  // Per face corner: position in the page in texels (x right, y down from the top row; texel
  // (i, j) covers [i, i+1) x [j, j+1)).
  std::vector<std::array<Vec2f, 3>> corner_px;
};

// Throws vf::Error for bad options or a mesh whose charts do not fit max_page_px at any texel
// size up to a metre.
UvAtlas buildUvAtlas(const TriangleMesh& mesh, const UvAtlasOptions& options = {});

// The mesh with its vertices split where charts meet, and `uvs` set (0..1, v up from the page's
// bottom row: OBJ's and Assimp's convention). Faces keep their order.
TriangleMesh applyAtlas(const TriangleMesh& mesh, const UvAtlas& atlas);

}  // namespace vf
