// Redwood folders (color/ or image/, depth/, a .log trajectory), see io/dataset_layouts.h.
#include <nlohmann/json.hpp>

#include <algorithm>
#include <filesystem>

#include "core/error.h"
#include "io/dataset_layouts.h"
#include "io/dataset_text.h"
#include "io/frame_order.h"
#include "io/json_fields.h"

namespace vf {
namespace {

namespace fs = std::filesystem;

// The images of `dir` in frame-number order (io/frame_order.h), dangling links included so that
// FrameListSource names them instead of the pairing going silently wrong.
std::vector<fs::path> imagesByNumber(const fs::path& dir) {
  std::vector<std::string> names;
  std::error_code ec;
  for (const auto& entry : fs::directory_iterator(dir, ec)) {
    const std::string ext = entry.path().extension().string();
    std::error_code type_ec;
    if ((entry.is_regular_file(type_ec) || entry.is_symlink(type_ec)) && (ext == ".png" || ext == ".jpg" || ext == ".jpeg"))
      names.push_back(entry.path().filename().string());
  }
  sortByFrameNumber(names, dir.string());
  std::vector<fs::path> out;
  for (const std::string& name : names) out.push_back(dir / name);
  return out;
}

fs::path colorFolder(const fs::path& dir) { return fs::is_directory(dir / "color") ? dir / "color" : dir / "image"; }

}  // namespace

void parseOpen3dIntrinsics(const std::string& text, const std::string& source, FrameList& list) {
  nlohmann::json j;
  try {
    j = nlohmann::json::parse(text);
  } catch (const nlohmann::json::exception& e) {
    throw Error(source + ": not valid JSON; expected Open3D's {\"width\", \"height\", \"intrinsic_matrix\"} (" +
                e.what() + ")");
  }
  const nlohmann::json& k = jsonArray(jsonMember(j, "intrinsic_matrix", "intrinsic_matrix", source), 9,
                                      "intrinsic_matrix", source);
  float m[9];
  for (size_t i = 0; i < 9; ++i) m[i] = jsonFloat(k[i], "intrinsic_matrix[" + std::to_string(i) + "]", source);
  list.expected_width = jsonInteger(jsonMember(j, "width", "width", source), 1, 100000, "width", source);
  list.expected_height = jsonInteger(jsonMember(j, "height", "height", source), 1, 100000, "height", source);
  if (m[1] != 0 || m[2] != 0 || m[3] != 0 || m[5] != 0 || m[8] != 1)
    throw Error(source + ": 'intrinsic_matrix' is not a column-major pinhole matrix [fx, 0, 0, 0, fy, 0, cx, cy, 1]");
  list.fx = m[0], list.fy = m[4], list.cx = m[6], list.cy = m[7];
  list.intrinsics_source = source;
}

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
    const std::string json = (dir / "camera-intrinsics.json").string();
    parseOpen3dIntrinsics(readTextFile(json, 1 << 20), json, list);
  } else {
    list.fx = list.fy = 525.f, list.cx = 319.5f, list.cy = 239.5f;
    list.intrinsics_source = "PrimeSense's 525, 525, 319.5, 239.5 (no camera-intrinsics.json)";
  }
  const std::vector<fs::path> depth = imagesByNumber(dir / "depth");
  const std::vector<fs::path> color = imagesByNumber(colorFolder(dir));
  if (!color.empty() && color.size() != depth.size())
    throw Error(folder + ": " + std::to_string(depth.size()) + " depth images but " + std::to_string(color.size()) +
                " colour images in " + colorFolder(dir).string() + " (they pair in frame-number order)");
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
