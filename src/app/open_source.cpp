#include "app/open_source.h"

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <filesystem>
#include <vector>

#include "core/error.h"
#include "core/similar_names.h"
#include "io/dataset_layouts.h"
#include "io/record3d.h"
#include "io/record3d_export.h"
#include "io/tum_dataset.h"

namespace vf::app {
namespace fs = std::filesystem;

const char* const kKnownLayouts =
    "  tum         TUM RGB-D folder (rgb.txt, depth.txt)\n"
    "  r3d         Record3D .r3d capture, or the folder it unzips to (metadata, rgbd/)\n"
    "  r3d-export  Record3D EXR+JPG export folder (metadata.json)\n"
    "  7scenes     7-Scenes / 3DMatch frame folder (frame-XXXXXX.depth.png, .color.jpg, .pose.txt)\n"
    "  replica     Replica in NICE-SLAM's layout (results/frameXXXXXX.jpg, depthXXXXXX.png, traj.txt)\n"
    "  scannet     ScanNet exported frames (color/, depth/, pose/, intrinsic/intrinsic_depth.txt)\n"
    "  redwood     Redwood folder (color/ or image/, depth/, a .log trajectory)";

namespace {

std::string unknownLayout(const std::string& path, const std::string& what) {
  return path + ": " + what + "; the known layouts are (--format forces one):\n" + kKnownLayouts;
}

// The layout of a folder, from the files it holds; empty when none fits.
std::string folderLayout(const fs::path& p) {
  if (fs::exists(p / "depth.txt") || fs::exists(p / "rgb.txt")) return "tum";
  if (fs::exists(p / "metadata.json")) return "r3d-export";
  if (fs::exists(p / "metadata") && fs::is_directory(p / "rgbd")) return "r3d";
  if (looksLikeSevenScenes(p.string())) return "7scenes";
  if (looksLikeReplica(p.string())) return "replica";
  if (looksLikeScanNet(p.string())) return "scannet";
  if (looksLikeRedwood(p.string())) return "redwood";
  return "";
}

// Sequences one level down ("office0 (replica)"): a dataset's download often wraps the frames in
// a scene folder (Replica's office0/, 7-Scenes' seq-01/), and the user names the wrapper.
std::vector<std::string> sequencesInside(const fs::path& dir) {
  std::vector<std::string> found;
  std::error_code ec;
  for (const auto& entry : fs::directory_iterator(dir, ec))
    if (entry.is_directory(ec)) {
      const std::string layout = folderLayout(entry.path());
      if (!layout.empty()) found.push_back(entry.path().filename().string() + " (" + layout + ")");
    }
  std::sort(found.begin(), found.end());
  return found;
}

std::string detectFormat(const std::string& path) {
  if (!fs::exists(path)) throw Error(noSuchPathMessage(path));
  const fs::path p(path);
  if (fs::is_regular_file(p)) {
    if (p.extension() == ".r3d") return "r3d";
    throw Error(unknownLayout(path, "not a known capture file"));
  }
  if (const std::string layout = folderLayout(p); !layout.empty()) return layout;
  if (const std::vector<std::string> inside = sequencesInside(p); !inside.empty()) {
    std::string list;
    for (size_t i = 0; i < inside.size() && i < 6; ++i) list += (i ? ", " : "") + inside[i];
    if (inside.size() > 6) list += ", ...";
    throw Error(path + ": not a sequence itself, but it holds " + std::to_string(inside.size()) + " (" + list +
                "); name the folder of the one to read, e.g. " + (p / inside[0].substr(0, inside[0].find(" ("))).string());
  }
  if (fs::is_directory(p / "results") || fs::exists(p / "traj.txt"))
    throw Error(unknownLayout(path, "looks like Replica but needs both results/ and traj.txt"));
  throw Error(unknownLayout(path, "not a folder of a known RGB-D layout"));
}

std::string number(double v) {
  char text[32];
  std::snprintf(text, sizeof text, "%g", v);
  return text;
}

struct Opened {
  std::unique_ptr<FrameSource> source;
  float units_per_metre = 1;  // the scale used
};

Opened openFormat(const std::string& path, const std::string& format, const SourceOptions& options) {
  const std::optional<float>& scale = options.depth_units_per_metre;
  if (format == "tum") {
    TumOptions tum;
    if (options.intrinsics) tum.intrinsics = parsePinholeOverride(*options.intrinsics);
    if (scale) tum.depth_units_per_metre = *scale;
    return {std::make_unique<TumDataset>(path, tum), tum.depth_units_per_metre};
  }
  if (format == "r3d" || format == "r3d-export") {
    if (options.intrinsics)
      throw Error(path + ": --intrinsics is not supported for Record3D captures (their metadata holds K)");
    if (options.min_confidence < 0 || options.min_confidence > 2)
      throw Error("--min-confidence " + std::to_string(options.min_confidence) +
                  ": ARKit confidence is 0 (low), 1 (medium) or 2 (high)");
    Record3dOptions r3d;
    r3d.min_confidence = options.min_confidence;
    if (scale) r3d.depth_units_per_metre = *scale;
    if (format == "r3d") {
      if (!fs::is_regular_file(path) && !fs::exists(fs::path(path) / "metadata"))
        throw Error(path + ": --format r3d expects a .r3d file or the folder it unzips to (metadata, rgbd/)");
      return {std::make_unique<Record3dCapture>(path, r3d), r3d.depth_units_per_metre};
    }
    if (!fs::is_directory(path)) throw Error(path + ": --format r3d-export expects a Record3D export folder");
    return {std::make_unique<Record3dExport>(path, r3d), r3d.depth_units_per_metre};
  }
  LayoutOptions layout;
  layout.depth_units_per_metre = scale;
  if (options.intrinsics) layout.intrinsics = parsePinholeOverride(*options.intrinsics);
  FrameList list;
  if (format == "7scenes" || format == "3dmatch")
    list = readSevenScenes(path, layout);
  else if (format == "replica")
    list = readReplica(path, layout);
  else if (format == "scannet")
    list = readScanNet(path, layout);
  else if (format == "redwood")
    list = readRedwood(path, layout);
  else
    throw Error("--format " + format + " is not a known layout; the known layouts are:\n" + kKnownLayouts);
  const float units = list.depth_units_per_metre;
  return {std::make_unique<FrameListSource>(std::move(list)), units};
}

// Median of the valid readings of the first frame that has some (of the first 10), in metres.
std::optional<double> firstMedianDepth(const FrameSource& source) {
  for (int i = 0; i < std::min(source.size(), 10); ++i) {
    const DepthImage depth = source.load(i).depth;
    std::vector<float> valid;
    const size_t n = size_t(depth.width()) * size_t(depth.height());
    for (size_t k = 0; k < n; ++k)
      if (std::isfinite(depth.data()[k]) && depth.data()[k] > 0.f) valid.push_back(depth.data()[k]);
    if (valid.empty()) continue;
    std::nth_element(valid.begin(), valid.begin() + valid.size() / 2, valid.end());
    return valid[valid.size() / 2];
  }
  return std::nullopt;
}

constexpr double kMinPlausibleDepth_m = 0.2, kMaxPlausibleDepth_m = 20.0;

void checkDepthScale(const FrameSource& source, const std::string& path, float units, bool user_scale) {
  const std::optional<double> median = firstMedianDepth(source);
  if (!median || (*median >= kMinPlausibleDepth_m && *median <= kMaxPlausibleDepth_m)) return;
  std::string message = path + ": the first frame's depth reads " + number(*median) +
                        " m (median of its valid pixels) at a depth scale of " + number(units) +
                        " units per metre" + (user_scale ? " (--depth-scale)" : "") + ", outside the plausible " +
                        number(kMinPlausibleDepth_m) + "-" + number(kMaxPlausibleDepth_m) + " m";
  // Which common scale would make it plausible (the raw median is median * units).
  for (const double candidate : {1000.0, 5000.0, 6553.5, 1.0}) {
    const double at = *median * units / candidate;
    if (candidate != units && at >= 0.3 && at <= 10) {
      message += "; at " + number(candidate) + " units per metre it would read " + number(at) + " m";
      break;
    }
  }
  message += ". Pass --depth-scale UNITS_PER_M (1000 = millimetres, 5000 = TUM, 6553.5 = Replica) if the depth is "
             "stored in other units.";
  if (!user_scale) throw Error(message);
  std::fprintf(stderr, "warning: %s\n", message.c_str());
}

}  // namespace

std::unique_ptr<FrameSource> openFrameSource(const std::string& path, const SourceOptions& options) {
  if (options.depth_units_per_metre && !(*options.depth_units_per_metre > 0 && std::isfinite(*options.depth_units_per_metre)))
    throw Error("--depth-scale " + number(*options.depth_units_per_metre) + ": expected depth units per metre > 0");
  const std::string format = options.format == "auto" ? detectFormat(path) : options.format;
  Opened opened = openFormat(path, format, options);
  checkDepthScale(*opened.source, path, opened.units_per_metre, options.depth_units_per_metre.has_value());
  return std::move(opened.source);
}

bool photometricTermWanted(const SourceOptions& options, const FrameSource& source, std::string* note) {
  if (options.photometric == "on") return true;
  if (options.photometric == "off") return false;
  if (options.photometric != "auto") throw Error("--photometric " + options.photometric + ": expected auto, on or off");
  if (source.colorRegisteredToDepth()) return true;
  if (note)
    *note = "photometric ICP term off: the colour of this input is not registered to its depth (--photometric on "
            "uses it anyway)";
  return false;
}

void addDatasetOptions(CLI::App& cmd, SourceOptions& options) {
  cmd.add_option("--depth-scale", options.depth_units_per_metre,
                 "Depth units per metre, overriding the input's own (1000 = mm, 5000 = TUM, 6553.5 = Replica)");
  cmd.add_option("--photometric", options.photometric,
                 "Photometric ICP term: on, off, or auto (off when colour is not registered to depth, as in "
                 "ScanNet and 7-Scenes)")
      ->capture_default_str()
      ->check(CLI::IsMember({"auto", "on", "off"}));
}

std::string datasetOptionsKey(const SourceOptions& options) {
  return "depth_scale=" + (options.depth_units_per_metre ? number(*options.depth_units_per_metre) : "") +
         ",photometric=" + options.photometric;
}

}  // namespace vf::app
