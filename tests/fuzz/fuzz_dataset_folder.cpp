// Fuzz target: whole dataset folders (7-Scenes/3DMatch, Replica, ScanNet, Redwood, TUM) built from
// the input, read by the layout's reader and opened as a frame source, frames 0-2 loaded. It
// reaches what the text targets cannot: file names and their numbering, pairing of colour with
// depth, poses with frames, the camera against the images, dangling links.
//
// Input: the first byte picks the layout (mod 5: 7-Scenes, Replica, ScanNet, Redwood, TUM); the
// rest is files, each a line "@@ relative/path" followed by its content up to the next "@@ " line.
// A content "DEPTH w h v" becomes a 16-bit PNG of w x h (at most 64 x 64) holding v, "COLOR w h"
// an RGB PNG, "LINK target" a symbolic link (relative); anything else is written as it is. Paths may hold
// letters, digits and "._-/" only, no "..": everything stays in a per-process temp folder.
#include <unistd.h>

#include <Eigen/Geometry>
#include <algorithm>
#include <cctype>
#include <cmath>
#include <cstdlib>
#include <filesystem>
#include <fstream>
#include <memory>
#include <set>
#include <sstream>
#include <string>

#include "core/camera_check.h"
#include "core/error.h"
#include "io/dataset_layouts.h"
#include "io/frame_list_source.h"
#include "io/image_codec.h"
#include "io/tum_dataset.h"

namespace {

namespace fs = std::filesystem;

bool safePath(const std::string& p) {
  if (p.empty() || p.size() > 80 || p[0] == '/' || p.find("..") != std::string::npos) return false;
  for (char c : p)
    if (!(std::isalnum(static_cast<unsigned char>(c)) || c == '.' || c == '_' || c == '-' || c == '/')) return false;
  return true;
}

void writeBytes(const fs::path& path, const std::string& bytes) {
  std::ofstream f(path, std::ios::binary);
  f.write(bytes.data(), std::streamsize(bytes.size()));
}

// One file of the input: an image, a link or text.
void materialise(const fs::path& path, const std::string& content) {
  std::error_code ec;
  fs::create_directories(path.parent_path(), ec);
  std::istringstream in(content);
  std::string kind;
  in >> kind;
  if (kind == "DEPTH" || kind == "COLOR") {
    int w = 0, h = 0, v = 0;
    in >> w >> h >> v;
    w = std::clamp(w, 1, 64), h = std::clamp(h, 1, 64);
    if (kind == "DEPTH") {
      std::vector<uint16_t> px(size_t(w) * h, uint16_t(v));
      writeBytes(path, vf::encodePng(px.data(), w, h, 1, 16, path.string()));
    } else {
      std::vector<uint8_t> px(size_t(w) * h * 3);
      for (size_t i = 0; i < px.size(); ++i) px[i] = uint8_t(i * 7 + v);
      writeBytes(path, vf::encodePng(px.data(), w, h, 3, 8, path.string()));
    }
  } else if (kind == "LINK") {
    std::string target;
    in >> target;
    if (safePath(target)) fs::create_symlink(target, path, ec);  // relative, inside the folder (or dangling)
  } else {
    writeBytes(path, content);
  }
}

void checkPose(const vf::Pose& p) {
  if (!p.matrix().allFinite()) std::abort();
  if ((p.linear().transpose() * p.linear() - Eigen::Matrix3d::Identity()).cwiseAbs().maxCoeff() > 1e-6) std::abort();
}

// What every frame source promises: a camera the pipeline can fuse, frames of its size, colour
// of the depth's size, finite rotations, no two frames at one time (and, for the numbered
// layouts, `ordered`: in time order).
void checkSource(const vf::FrameSource& source, bool ordered) {
  if (source.size() < 1) std::abort();
  const vf::Intrinsics k = source.depthIntrinsics();
  if (!vf::cameraProblem(k).empty()) std::abort();
  std::set<double> seen_us;
  double last_t = -INFINITY;
  for (int i = 0; i < std::min(source.size(), 3); ++i) {
    const vf::RgbdFrame f = source.load(i);
    if (f.depth.width() != k.width || f.depth.height() != k.height) std::abort();
    if (!f.color.empty() && (f.color.width() != k.width || f.color.height() != k.height)) std::abort();
    if (f.T_world_cam_given) checkPose(*f.T_world_cam_given);
    if (!seen_us.insert(std::round(f.timestamp * 1e6)).second) std::abort();
    if (ordered && !(f.timestamp > last_t)) std::abort();
    last_t = f.timestamp;
  }
}

void checkList(const vf::FrameList& list) {
  std::set<std::string> names;
  double last_t = -INFINITY;
  for (const vf::FrameFiles& f : list.frames) {
    if (!names.insert(f.name).second) std::abort();  // a frame twice
    if (!(f.timestamp > last_t)) std::abort();          // out of number order
    last_t = f.timestamp;
    if (f.T_world_cam) checkPose(*f.T_world_cam);
  }
}

}  // namespace

extern "C" int LLVMFuzzerTestOneInput(const uint8_t* data, size_t size) {
  if (size < 1) return 0;
  const char* tmp = std::getenv("TMPDIR");
  const fs::path dir = fs::path(tmp && *tmp ? tmp : "/tmp") / ("vdbfuse_fuzz_folder_" + std::to_string(::getpid()));
  std::error_code ec;
  fs::remove_all(dir, ec);
  fs::create_directories(dir / "scene", ec);
  const int layout = data[0] % 5;
  const std::string text(reinterpret_cast<const char*>(data) + 1, size - 1);

  // Split into files: "@@ path\n" then content.
  std::vector<std::pair<std::string, std::string>> files;
  for (size_t at = text.find("@@ "); at != std::string::npos;) {
    const size_t eol = text.find('\n', at);
    if (eol == std::string::npos) break;
    const std::string path = text.substr(at + 3, eol - at - 3);
    const size_t next = text.find("\n@@ ", eol);
    const size_t end = next == std::string::npos ? text.size() : next + 1;
    files.emplace_back(path, text.substr(eol + 1, end - eol - 1));
    at = next == std::string::npos ? next : next + 1;
  }
  if (files.size() > 40) return 0;
  for (const auto& [path, content] : files)
    if (safePath(path)) materialise(dir / path, content);

  // Folders one level down, so that Replica's and 3DMatch's files "one folder up" stay inside.
  const std::string folder = (dir / "scene").string();
  try {
    if (layout == 4) {
      const vf::TumDataset tum(folder);
      checkSource(tum, /*ordered=*/false);
    } else {
      const vf::FrameList list = layout == 0   ? vf::readSevenScenes(folder)
                                 : layout == 1 ? vf::readReplica(folder)
                                 : layout == 2 ? vf::readScanNet(folder)
                                               : vf::readRedwood(folder);
      checkList(list);
      const vf::FrameListSource source(list);
      checkSource(source, /*ordered=*/true);
    }
  } catch (const vf::Error&) {
  }
  fs::remove_all(dir, ec);
  return 0;
}
