// Redwood folders (color/ or image/, depth/, a .log trajectory), see io/dataset_layouts.h.
#include <nlohmann/json.hpp>

#include <algorithm>
#include <filesystem>

#include "core/error.h"
#include "io/dataset_layouts.h"
#include "io/dataset_text.h"

namespace vf {
namespace {

namespace fs = std::filesystem;

std::vector<fs::path> sortedImages(const fs::path& dir) {
  std::vector<fs::path> out;
  std::error_code ec;
  for (const auto& entry : fs::directory_iterator(dir, ec)) {
    const std::string ext = entry.path().extension().string();
    if (entry.is_regular_file() && (ext == ".png" || ext == ".jpg" || ext == ".jpeg")) out.push_back(entry.path());
  }
  std::sort(out.begin(), out.end());
  return out;
}

fs::path colorFolder(const fs::path& dir) { return fs::is_directory(dir / "color") ? dir / "color" : dir / "image"; }

// Open3D's PinholeCameraIntrinsic JSON: width, height, intrinsic_matrix (3x3 column-major).
void readOpen3dIntrinsics(const fs::path& path, FrameList& list) {
  try {
    const nlohmann::json j = nlohmann::json::parse(readTextFile(path.string(), 1 << 20));
    const std::vector<double> k = j.at("intrinsic_matrix").get<std::vector<double>>();
    if (k.size() != 9) throw Error(path.string() + ": 'intrinsic_matrix' must hold 9 numbers");
    list.expected_width = j.at("width").get<int>();
    list.expected_height = j.at("height").get<int>();
    list.fx = float(k[0]), list.fy = float(k[4]), list.cx = float(k[6]), list.cy = float(k[7]);
  } catch (const nlohmann::json::exception& e) {
    throw Error(path.string() + ": expected Open3D's {\"width\", \"height\", \"intrinsic_matrix\"} (" + e.what() + ")");
  }
  list.intrinsics_source = path.string();
}

}  // namespace

bool looksLikeRedwood(const std::string& folder) {
  const fs::path dir(folder);
  return fs::is_directory(dir / "depth") && fs::is_directory(colorFolder(dir)) && !looksLikeScanNet(folder);
}

FrameList readRedwood(const std::string& folder, const LayoutOptions& options) {
  const fs::path dir(folder);
  FrameList list;
  list.folder = folder;
  list.layout = "Redwood";
  list.depth_units_per_metre = 1000;
  list.depth_scale_source = "millimetres, as Redwood stores depth";
  if (fs::exists(dir / "camera-intrinsics.json")) {
    readOpen3dIntrinsics(dir / "camera-intrinsics.json", list);
  } else {
    list.fx = list.fy = 525.f, list.cx = 319.5f, list.cy = 239.5f;
    list.intrinsics_source = "PrimeSense's 525, 525, 319.5, 239.5 (no camera-intrinsics.json)";
  }
  const std::vector<fs::path> depth = sortedImages(dir / "depth");
  const std::vector<fs::path> color = sortedImages(colorFolder(dir));
  if (!color.empty() && color.size() != depth.size())
    throw Error(folder + ": " + std::to_string(depth.size()) + " depth images but " + std::to_string(color.size()) +
                " colour images in " + colorFolder(dir).string() + " (they pair by sorted name)");
  std::vector<fs::path> logs;
  std::error_code ec;
  for (const auto& entry : fs::directory_iterator(dir, ec))
    if (entry.path().extension() == ".log") logs.push_back(entry.path());
  std::sort(logs.begin(), logs.end());
  if (logs.size() > 1)
    throw Error(folder + ": several .log trajectories (" + logs[0].filename().string() + ", " +
                logs[1].filename().string() + "); keep one beside color/ and depth/");
  for (size_t i = 0; i < depth.size(); ++i) {
    FrameFiles f;
    f.name = depth[i].stem().string();
    f.depth = depth[i].string();
    if (!color.empty()) f.color = color[i].string();
    f.timestamp = double(i) / kDatasetFrameRateHz;
    list.frames.push_back(std::move(f));
  }
  if (list.frames.empty()) throw Error(folder + "/depth: no depth images (not a Redwood folder)");
  if (!logs.empty()) {
    for (const LogEntry& e : parseLogTrajectory(readTextFile(logs[0].string()), logs[0].string())) {
      if (size_t(e.frame) >= list.frames.size())
        throw Error(logs[0].string() + ": a pose for frame " + std::to_string(e.frame) + " but depth/ holds " +
                    std::to_string(list.frames.size()) + " images");
      list.frames[size_t(e.frame)].T_world_cam = e.T_world_cam;
    }
  }
  applyLayoutOptions(list, options);
  return list;
}

}  // namespace vf
