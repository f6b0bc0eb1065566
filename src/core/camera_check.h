#pragma once
// Whether a pinhole camera can be fused at its image size: the readers ask before a frame is read,
// so that a bad camera-intrinsics.txt, cam_params.json or Record3D K is reported against its file
// (the fusion pipeline's own check names only the Intrinsics field). Same bounds as the pipeline's
// validateCamera (src/fusion/pipeline_buffers.h).
#include <string>

#include "core/intrinsics.h"

namespace vf {

// "" when the camera is usable; else what is wrong, e.g. "cx = 3200 lies outside the 640-pixel-wide
// image (the principal point must lie inside it)". Focal lengths must give a field of view between
// 179 and 1 degrees: 0.005 to 60 times the image side.
std::string cameraProblem(const Intrinsics& k);

}  // namespace vf
