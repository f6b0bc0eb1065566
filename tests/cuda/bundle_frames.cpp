// bundle_frames: a compact copy of a TUM folder for the GPU bundle (scripts/gpu_bundle.sh), so
// that both shared captures fit its 48 MiB: frames as TumDataset delivers them (associated, and
// undistorted where the calibration has distortion), depth as 16-bit PNG with adaptive filters
// (lossless, 71 % of TUM's own PNGs), colour as JPEG, one colour image per depth frame under the depth timestamp, the
// ground truth as it is, and camera_intrinsics.txt holding the pinhole alone (the frames are
// already undistorted).
//
//   bundle_frames SOURCE_TUM_FOLDER TARGET_FOLDER [--jpeg-quality Q (default 92)]
//
// Exit status: 0 written, 1 error, 2 bad arguments. The target folder must not exist yet: it is
// written beside itself and renamed into place, so an interrupted run leaves no half copy.
#include <cstdio>
#include <cstdlib>
#include <filesystem>
#include <fstream>
#include <sstream>
#include <string>

#include "core/atomic_output.h"
#include "core/error.h"
#include "io/image_codec.h"
#include "io/image_io.h"
#include "io/tum_dataset.h"

namespace {

namespace fs = std::filesystem;

std::string readText(const std::string& path) {
  std::ifstream in(path, std::ios::binary);
  if (!in) throw vf::Error("cannot read " + path);
  std::ostringstream s;
  s << in.rdbuf();
  return s.str();
}

void writeCompactCopy(const std::string& source, const std::string& target, int jpeg_quality) {
  if (fs::exists(target)) throw vf::Error(target + " already exists; remove it first");
  const vf::TumDataset dataset(source);
  const fs::path temp = fs::path(target).parent_path() / ("." + fs::path(target).filename().string() + ".partial");
  fs::remove_all(temp);
  fs::create_directories(temp / "depth");
  fs::create_directories(temp / "rgb");
  std::string depth_list = "# depth maps: 16-bit PNG, value / 5000 = metres (compact copy of " + source + ")\n";
  std::string rgb_list = "# colour images: JPEG quality " + std::to_string(jpeg_quality) + ", undistorted like the depth\n";
  size_t depth_bytes = 0, rgb_bytes = 0;
  for (int i = 0; i < dataset.size(); ++i) {
    const vf::RgbdFrame frame = dataset.load(i);
    if (frame.color.empty()) throw vf::Error(dataset.depthPath(i) + " has no colour image; a compact copy needs one per frame");
    char stamp[32];
    std::snprintf(stamp, sizeof stamp, "%.6f", frame.timestamp);
    const std::string depth_name = "depth/" + std::string(stamp) + ".png";
    const std::string rgb_name = "rgb/" + std::string(stamp) + ".jpg";
    std::vector<uint16_t> units(size_t(frame.depth.width()) * frame.depth.height());
    for (size_t p = 0; p < units.size(); ++p) {
      // Exact: TUM depth is value / 5000 and nearest-neighbour undistortion keeps the values.
      const float v = frame.depth.data()[p] * vf::kTumDepthUnitsPerMetre + 0.5f;
      units[p] = uint16_t(v > 65535.f ? 65535.f : v);
    }
    const std::string png = vf::encodePng(units.data(), frame.depth.width(), frame.depth.height(), 1, 16,
                                          depth_name, vf::PngCompression::Compact);
    const std::string jpg = vf::encodeJpeg(frame.color, jpeg_quality, rgb_name);
    vf::writeFileAtomic((temp / depth_name).string(), png);
    vf::writeFileAtomic((temp / rgb_name).string(), jpg);
    depth_bytes += png.size();
    rgb_bytes += jpg.size();
    depth_list += std::string(stamp) + " " + depth_name + "\n";
    rgb_list += std::string(stamp) + " " + rgb_name + "\n";
  }
  vf::writeFileAtomic((temp / "depth.txt").string(), depth_list);
  vf::writeFileAtomic((temp / "rgb.txt").string(), rgb_list);
  const vf::Intrinsics k = dataset.depthIntrinsics();
  char calib[160];
  std::snprintf(calib, sizeof calib, "# pinhole of the undistorted frames (from %s)\n%.6f %.6f %.6f %.6f\n",
                dataset.calibration().source.c_str(), k.fx, k.fy, k.cx, k.cy);
  vf::writeFileAtomic((temp / "camera_intrinsics.txt").string(), calib);
  const fs::path truth = fs::path(source) / "groundtruth.txt";
  if (fs::exists(truth)) vf::writeFileAtomic((temp / "groundtruth.txt").string(), readText(truth.string()));
  fs::rename(temp, target);
  std::printf("%s: %d frames, depth %.1f MiB, colour %.1f MiB\n", target.c_str(), dataset.size(),
              double(depth_bytes) / (1 << 20), double(rgb_bytes) / (1 << 20));
}

}  // namespace

int main(int argc, char** argv) {
  if (argc != 3 && !(argc == 5 && std::string(argv[3]) == "--jpeg-quality")) {
    std::fprintf(stderr, "usage: bundle_frames SOURCE_TUM_FOLDER TARGET_FOLDER [--jpeg-quality Q]\n");
    return 2;
  }
  const int quality = argc == 5 ? std::atoi(argv[4]) : 92;
  try {
    writeCompactCopy(argv[1], argv[2], quality);
    return 0;
  } catch (const vf::Error& e) {
    std::fprintf(stderr, "bundle_frames: %s\n", e.what());
    return 1;
  } catch (const std::filesystem::filesystem_error& e) {
    std::fprintf(stderr, "bundle_frames: %s\n", e.what());
    return 1;
  }
}
