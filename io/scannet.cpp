// ScanNet's exported frames (SensReader's reader.py: color/ depth/ pose/ intrinsic/), see
// io/dataset_layouts.h.
#include <algorithm>
#include <filesystem>

#include "core/error.h"
#include "io/dataset_layouts.h"
#include "io/dataset_text.h"

namespace vf {
namespace {
namespace fs = std::filesystem;
}

bool looksLikeScanNet(const std::string& folder) {
  const fs::path dir(folder);
  return fs::is_directory(dir / "depth") && fs::is_directory(dir / "pose") &&
         fs::exists(dir / "intrinsic" / "intrinsic_depth.txt");
}

FrameList readScanNet(const std::string& folder, const LayoutOptions& options) {
  const fs::path dir(folder);
  FrameList list;
  list.folder = folder;
  list.layout = "ScanNet";
  list.depth_units_per_metre = 1000;
  list.depth_scale_source = "millimetres, as ScanNet exports depth";
  // The iPad's colour camera and the Structure depth sensor: different sensors, different sizes.
  list.color_registered = false;
  list.resize_color = true;
  const std::string intrinsics = (dir / "intrinsic" / "intrinsic_depth.txt").string();
  const PinholeMatrix k = parseIntrinsicMatrix(readTextFile(intrinsics, 1 << 20), intrinsics);
  list.fx = k.fx, list.fy = k.fy, list.cx = k.cx, list.cy = k.cy;
  list.intrinsics_source = intrinsics;

  for (const NumberedFile& n : numberedFiles((dir / "depth").string(), "", ".png")) {
    const std::string& stem = n.digits;
    FrameFiles f;
    f.name = stem;
    f.depth = (dir / "depth" / (stem + ".png")).string();
    f.color = presentFile({(dir / "color" / (stem + ".png")).string(), (dir / "color" / (stem + ".jpg")).string()});
    const std::string pose = presentFile({(dir / "pose" / (stem + ".txt")).string()});
    if (!pose.empty()) f.T_world_cam = readPoseMatrixFile(pose);  // -inf (lost): none
    f.timestamp = double(n.number) / kDatasetFrameRateHz;
    list.frames.push_back(std::move(f));
  }
  if (list.frames.empty()) throw Error(folder + "/depth: no N.png depth frames (not a ScanNet export)");
  applyLayoutOptions(list, options);
  return list;
}

}  // namespace vf
