#pragma once
// The colour of every texel of an atlas page, from the input frames at their poses
// (bake_view.h): per face, the few frames that see it best; per texel, the best of those that
// see its point unoccluded and unmasked, blended; texels no frame saw take the mesh's vertex
// colours (the fused voxel colour); finally chart colours spill into the gutters.
#include <cstddef>
#include <functional>
#include <vector>

#include "core/image.h"
#include "core/mesh.h"
#include "texture/bake_view.h"
#include "texture/uv_atlas.h"

namespace vf {

struct BakeOptions {
  BakeSampleParams sample;
  int views_per_face = 6;  // candidate frames kept per face
  int blend_views = 3;     // a texel blends at most this many of them, the best weighted
  bool equalise_exposure = true;  // per-frame colour gains that make overlapping frames agree
  // Called now and then with the faces baked so far and their total, from one thread at a time
  // (whichever worker finished a chart; calls that would wait for another are skipped).
  std::function<void(size_t done, size_t total)> on_progress;
};

struct BakeReport {
  size_t texels = 0;              // texels inside charts
  size_t from_frames = 0;         // of them, coloured from frames
  size_t from_fallback = 0;       // from the vertex colours (no frame saw them)
  size_t faces_unseen = 0;        // faces without a candidate frame
  double select_s = 0, bake_s = 0, dilate_s = 0;
  std::vector<Vec3f> gains;       // the exposure gain of each view
};

// `mesh` in the frame the views' poses are in (the scene's), with the faces `atlas` was built
// for; its vertex colours fill unseen texels. `views` may be empty (all from the fallback).
// Returns the page (page_px square, sRGB). Parallel over faces and charts.
ColorImage bakeTexture(const TriangleMesh& mesh, const UvAtlas& atlas, std::vector<BakeView> views,
                       const BakeOptions& options = {}, BakeReport* report = nullptr);

// A frame's sharpness: the variance of the Laplacian of its grey image (at half size): blurred
// frames (the camera moving fast) score low.
double imageSharpness(const ColorImage& color);

}  // namespace vf
