// Replica in NICE-SLAM's layout (io/dataset_layouts.h).
#include <nlohmann/json.hpp>

#include <algorithm>
#include <filesystem>

#include "core/error.h"
#include "io/dataset_layouts.h"
#include "io/dataset_text.h"

namespace vf {
namespace {

namespace fs = std::filesystem;

// cam_params.json: {"camera": {"w", "h", "fx", "fy", "cx", "cy", "scale"}} (NICE-SLAM's export).
void readCamParams(const fs::path& path, FrameList& list) {
  nlohmann::json j;
  try {
    j = nlohmann::json::parse(readTextFile(path.string(), 1 << 20));
    const nlohmann::json& c = j.at("camera");
    list.expected_width = c.at("w").get<int>();
    list.expected_height = c.at("h").get<int>();
    list.fx = c.at("fx").get<float>(), list.fy = c.at("fy").get<float>();
    list.cx = c.at("cx").get<float>(), list.cy = c.at("cy").get<float>();
    list.depth_units_per_metre = c.at("scale").get<float>();
  } catch (const nlohmann::json::exception& e) {
    throw Error(path.string() + ": expected {\"camera\": {\"w\", \"h\", \"fx\", \"fy\", \"cx\", \"cy\", \"scale\"}} (" +
                e.what() + ")");
  }
  if (list.expected_width <= 0 || list.expected_height <= 0 || list.expected_width > 100000 ||
      list.expected_height > 100000)
    throw Error(path.string() + ": camera w and h must be positive image sizes");
  list.intrinsics_source = path.string();
  list.depth_scale_source = path.string() + " 'scale'";
}

}  // namespace

bool looksLikeReplica(const std::string& folder) {
  const fs::path dir(folder);
  return fs::is_directory(dir / "results") && fs::exists(dir / "traj.txt");
}

FrameList readReplica(const std::string& folder, const LayoutOptions& options) {
  const fs::path dir(folder);
  FrameList list;
  list.folder = folder;
  list.layout = "Replica";
  const fs::path here = dir / "cam_params.json";
  const fs::path up = fs::absolute(dir).lexically_normal().parent_path() / "cam_params.json";
  if (fs::exists(here)) {
    readCamParams(here, list);
  } else if (fs::exists(up)) {
    readCamParams(up, list);
  } else {
    // NICE-SLAM's configs/Replica/replica.yaml, the values every Replica sequence was rendered with.
    list.expected_width = 1200, list.expected_height = 680;
    list.fx = list.fy = 600.f, list.cx = 599.5f, list.cy = 339.5f;
    list.depth_units_per_metre = 6553.5f;
    list.intrinsics_source = "NICE-SLAM's Replica camera 1200x680, 600, 600, 599.5, 339.5 (no cam_params.json)";
    list.depth_scale_source = "NICE-SLAM's Replica png_depth_scale";
  }
  const std::string traj_path = (dir / "traj.txt").string();
  const std::vector<Pose> poses = parseReplicaTrajectory(readTextFile(traj_path), traj_path);

  for (const auto& [number, digits] : numberedFiles((dir / "results").string(), "depth", ".png")) {
    if (size_t(number) >= poses.size())
      throw Error(traj_path + " holds " + std::to_string(poses.size()) + " poses but results/ has depth" + digits +
                  ".png (one pose per frame, in frame order)");
    FrameFiles f;
    f.name = "frame" + digits;
    f.depth = (dir / "results" / ("depth" + digits + ".png")).string();
    for (const char* ext : {".jpg", ".png"})
      if (fs::exists(dir / "results" / (f.name + ext))) f.color = (dir / "results" / (f.name + ext)).string();
    f.T_world_cam = poses[size_t(number)];
    f.timestamp = double(number) / kDatasetFrameRateHz;
    list.frames.push_back(std::move(f));
  }
  if (list.frames.empty()) throw Error(folder + "/results: no depthXXXXXX.png (not a Replica folder)");
  applyLayoutOptions(list, options);
  return list;
}

}  // namespace vf
