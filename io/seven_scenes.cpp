// 7-Scenes / 3DMatch frame folders (io/dataset_layouts.h).
#include <algorithm>
#include <filesystem>

#include "core/error.h"
#include "io/dataset_layouts.h"
#include "io/dataset_text.h"

namespace vf {

namespace fs = std::filesystem;

bool looksLikeSevenScenes(const std::string& folder) {
  std::error_code ec;
  for (const auto& entry : fs::directory_iterator(folder, ec)) {
    const std::string name = entry.path().filename().string();
    if (name.rfind("frame-", 0) == 0 && name.size() > 10 && name.compare(name.size() - 10, 10, ".depth.png") == 0)
      return true;
  }
  return false;
}

FrameList readSevenScenes(const std::string& folder, const LayoutOptions& options) {
  FrameList list;
  list.folder = folder;
  list.layout = "7-Scenes/3DMatch";
  list.depth_units_per_metre = 1000;
  list.depth_scale_source = "millimetres, as 7-Scenes and 3DMatch store depth";
  list.depth_invalid_value = 65535;
  // The Kinect's colour and depth cameras are not registered to each other: colour pixel (u, v)
  // sees nearly what depth pixel (u, v) sees, off by the sensors' parallax (a few pixels at 1-2
  // m, more up close). The photometric term then pulls the pose towards where the colour edges
  // sit in the other camera: on redkitchen_head500 ATE 4.57 cm with it, 2.60 cm without (depth
  // noise weighting on; 6.51 / 4.96 without it); head100 1.07 / 0.96. So colour is fused onto the
  // surface as before, but tracking is geometric (--photometric on overrides).
  list.color_registered = false;
  const fs::path dir(folder);
  // 3DMatch keeps camera-intrinsics.txt in the scene folder, above its seq-XX frame folders.
  fs::path intrinsics = dir / "camera-intrinsics.txt";
  if (!fs::exists(intrinsics)) intrinsics = fs::absolute(dir).lexically_normal().parent_path() / "camera-intrinsics.txt";
  if (fs::exists(intrinsics)) {
    const PinholeMatrix k = parseIntrinsicMatrix(readTextFile(intrinsics.string(), 1 << 20), intrinsics.string());
    list.fx = k.fx, list.fy = k.fy, list.cx = k.cx, list.cy = k.cy;
    list.intrinsics_source = intrinsics.string();
  } else {
    list.fx = list.fy = 585.f, list.cx = 320.f, list.cy = 240.f;
    list.intrinsics_source = "7-Scenes' documented 585, 585, 320, 240 (no camera-intrinsics.txt)";
  }
  for (const auto& [number, digits] : numberedFiles(folder, "frame-", ".depth.png")) {
    const std::string stem = "frame-" + digits;
    FrameFiles f;
    f.name = stem;
    f.depth = (dir / (stem + ".depth.png")).string();
    f.color = presentFile({(dir / (stem + ".color.jpg")).string(), (dir / (stem + ".color.png")).string()});
    const std::string pose = presentFile({(dir / (stem + ".pose.txt")).string()});
    if (!pose.empty()) f.T_world_cam = readPoseMatrixFile(pose);
    f.timestamp = double(number) / kDatasetFrameRateHz;
    list.frames.push_back(std::move(f));
  }
  if (list.frames.empty()) throw Error(folder + ": no frame-XXXXXX.depth.png (not a 7-Scenes/3DMatch frame folder)");
  applyLayoutOptions(list, options);
  return list;
}

}  // namespace vf
