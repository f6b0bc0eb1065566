#pragma once
// Opens whatever RGB-D input a path names: a TUM folder, a Record3D .r3d capture, or a Record3D
// EXR+JPG export folder (detected from the path; `format` forces one).
#include <memory>
#include <optional>
#include <string>

#include "core/frame.h"

namespace vf::app {

struct SourceOptions {
  std::string format = "auto";               // auto | tum | r3d | r3d-export
  std::optional<std::string> intrinsics;     // "fx,fy,cx,cy" override
  int min_confidence = 2;                    // Record3D depth confidence threshold
};

std::unique_ptr<FrameSource> openFrameSource(const std::string& path, const SourceOptions& options);

}  // namespace vf::app
