#include "app/open_source.h"

#include <filesystem>

#include "core/error.h"
#include "io/record3d.h"
#include "io/record3d_export.h"
#include "io/tum_dataset.h"

namespace vf::app {
namespace fs = std::filesystem;

namespace {

std::string detectFormat(const std::string& path) {
  if (!fs::exists(path)) throw Error(path + ": no such file or folder");
  if (fs::is_regular_file(path)) {
    if (fs::path(path).extension() == ".r3d") return "r3d";
    throw Error(path + ": not a known capture file (expected a .r3d file, a Record3D export folder or a TUM folder)");
  }
  if (fs::exists(fs::path(path) / "depth.txt") || fs::exists(fs::path(path) / "rgb.txt")) return "tum";
  if (fs::exists(fs::path(path) / "metadata.json")) return "r3d-export";
  throw Error(path + ": not a TUM folder (no rgb.txt / depth.txt) nor a Record3D export (no metadata.json)");
}

}  // namespace

std::unique_ptr<FrameSource> openFrameSource(const std::string& path, const SourceOptions& options) {
  const std::string format = options.format == "auto" ? detectFormat(path) : options.format;
  if (format == "tum") {
    TumOptions tum;
    if (options.intrinsics) tum.intrinsics = parsePinholeOverride(*options.intrinsics);
    return std::make_unique<TumDataset>(path, tum);
  }
  if (format == "r3d" || format == "r3d-export") {
    if (options.intrinsics)
      throw Error(path + ": --intrinsics is not supported for Record3D captures (their metadata holds K)");
    if (options.min_confidence < 0 || options.min_confidence > 2)
      throw Error("--min-confidence " + std::to_string(options.min_confidence) +
                  ": ARKit confidence is 0 (low), 1 (medium) or 2 (high)");
    Record3dOptions r3d;
    r3d.min_confidence = options.min_confidence;
    if (format == "r3d") {
      if (!fs::is_regular_file(path)) throw Error(path + ": --format r3d expects a .r3d file");
      return std::make_unique<Record3dCapture>(path, r3d);
    }
    if (!fs::is_directory(path)) throw Error(path + ": --format r3d-export expects a Record3D export folder");
    return std::make_unique<Record3dExport>(path, r3d);
  }
  throw Error(path + ": input format '" + format + "' is not supported (expected auto, tum, r3d or r3d-export)");
}

}  // namespace vf::app
