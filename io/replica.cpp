// Replica in NICE-SLAM's layout (io/dataset_layouts.h).
#include <nlohmann/json.hpp>

#include <algorithm>
#include <filesystem>

#include "core/error.h"
#include "io/dataset_layouts.h"
#include "io/dataset_text.h"
#include "io/json_fields.h"

namespace vf {
namespace {

namespace fs = std::filesystem;

void readCamParams(const fs::path& path, FrameList& list) {
  parseReplicaCamParams(readTextFile(path.string(), 1 << 20), path.string(), list);
}

}  // namespace

void parseReplicaCamParams(const std::string& text, const std::string& source, FrameList& list) {
  nlohmann::json j;
  try {
    j = nlohmann::json::parse(text);
  } catch (const nlohmann::json::exception& e) {
    throw Error(source + ": not valid JSON; expected {\"camera\": {\"w\", \"h\", \"fx\", \"fy\", \"cx\", \"cy\", "
                "\"scale\"}} (" + e.what() + ")");
  }
  const nlohmann::json& c = jsonMember(j, "camera", "camera", source);
  auto field = [&](const char* key) -> const nlohmann::json& {
    return jsonMember(c, key, std::string("camera.") + key, source);
  };
  list.expected_width = jsonInteger(field("w"), 1, 100000, "camera.w", source);
  list.expected_height = jsonInteger(field("h"), 1, 100000, "camera.h", source);
  list.fx = jsonFloat(field("fx"), "camera.fx", source), list.fy = jsonFloat(field("fy"), "camera.fy", source);
  list.cx = jsonFloat(field("cx"), "camera.cx", source), list.cy = jsonFloat(field("cy"), "camera.cy", source);
  list.depth_units_per_metre = jsonFloat(field("scale"), "camera.scale", source);
  if (!(list.depth_units_per_metre > 0))
    throw Error(source + ": 'camera.scale' must be a positive number of depth units per metre, got " +
                field("scale").dump());
  list.intrinsics_source = source;
  list.depth_scale_source = source + " 'scale'";
}

bool looksLikeReplica(const std::string& folder) {
  const fs::path dir(folder);
  return fs::is_directory(dir / "results") && fs::exists(dir / "traj.txt");
}

FrameList readReplica(const std::string& folder, const LayoutOptions& options) {
  const fs::path dir(folder);
  FrameList list;
  list.folder = folder;
  list.layout = "Replica";
  list.depth_noise_quadratic = 0.f;  // rendered depth: no reading is noisier for being far
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
    f.color = presentFile({(dir / "results" / (f.name + ".png")).string(), (dir / "results" / (f.name + ".jpg")).string()});
    f.T_world_cam = poses[size_t(number)];
    f.timestamp = double(number) / kDatasetFrameRateHz;
    list.frames.push_back(std::move(f));
  }
  if (list.frames.empty()) throw Error(folder + "/results: no depthXXXXXX.png (not a Replica folder)");
  applyLayoutOptions(list, options);
  return list;
}

}  // namespace vf
