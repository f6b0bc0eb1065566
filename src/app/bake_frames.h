#pragma once
// The input frames of a scene, opened again for a texture bake (texture/texture_bake.h): the
// capture the scene records (or --frames), the poses it was fused at (the scene's metadata, the
// trajectory beside it, or --trajectory), and masks of the classes never to paint (people).
#include <set>
#include <string>
#include <vector>

#include "core/image.h"
#include "texture/bake_view.h"
#include "vdb/scene.h"

namespace vf::app {

struct BakeFrameOptions {
  std::string frames;      // the capture; empty: the one the scene records
  std::string trajectory;  // TUM file; empty: the scene's metadata, else <scene>.txt
  std::string labels;      // label maps; empty: the folder the scene was fused with
  int max_frames = 300;    // at most this many frames, evenly spaced (memory: ~3 MB each for an iPhone)
  int mask_dilation_px = 4;  // masked classes grow by this many depth pixels
};

struct BakeFrames {
  std::vector<ColorImage> color;
  std::vector<DepthImage> depth;
  std::vector<Image<uint8_t>> mask;  // empty images where nothing is masked
  std::vector<BakeView> views;       // views into the images above
  std::string capture, poses_from;   // what was read, for the report
  int frames_in_capture = 0, frames_posed = 0, frames_blurred = 0, frames_unlabelled = 0;
};

// Throws vf::Error naming the capture or trajectory and the option that would fix it.
BakeFrames loadBakeFrames(const Scene& scene, const std::string& scene_path, const std::set<int>& masked_classes,
                          const BakeFrameOptions& options);

}  // namespace vf::app
