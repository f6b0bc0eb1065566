#include "io/tum_writer.h"

#include <tbb/parallel_for.h>

#include <cmath>
#include <cstdio>
#include <filesystem>
#include <mutex>
#include <optional>
#include <sstream>
#include <vector>

#include "core/atomic_output.h"
#include "core/error.h"
#include "io/frame_list_source.h"
#include "io/image_codec.h"
#include "io/image_io.h"

namespace vf {
namespace fs = std::filesystem;

std::string tumTimestampString(double t) {
  char buf[64];
  std::snprintf(buf, sizeof buf, "%.6f", t);
  return buf;
}

namespace {

// Encoded in memory, then written through a temp file and renamed (io/image_io.h). Not
// writeDepthPng: that one clamps to 65535, a converted dataset writes no reading instead.
void writeDepthPngOrNoReading(const fs::path& target, const DepthImage& depth) {
  std::vector<uint16_t> units(size_t(depth.width()) * depth.height());
  for (int y = 0; y < depth.height(); ++y)
    for (int x = 0; x < depth.width(); ++x) {
      const double u = std::round(double(depth(x, y)) * double(kTumDepthUnitsPerMetre));
      // Beyond 13.1 m a 16-bit value cannot hold the depth; no reading beats a wrong one.
      units[size_t(y) * depth.width() + x] = (std::isfinite(u) && u > 0 && u <= 65535) ? uint16_t(u) : 0;
    }
  writeFileAtomic(target.string(), encodePng(units.data(), depth.width(), depth.height(), 1, 16, target.string()));
}

struct FrameRecord {
  double timestamp = 0;
  bool has_color = false;
  std::optional<Pose> pose;
};

std::string listHeader(const char* what, const std::string& description) {
  return std::string("# ") + what + "\n# written by vdbfuse convert from " + description +
         "\n# timestamp filename\n";
}

}  // namespace

TumWriteResult writeTumFolder(const FrameSource& source, const std::string& folder,
                              const TumWriteOptions& options) {
  // Everything goes into a temporary folder, which replaces `folder` only once complete.
  AtomicFolder output(folder);
  const fs::path dir(output.tempPath());
  std::error_code ec;
  // create_directory, not create_directories: if a signal's cleanup has removed the temporary
  // folder, this must fail rather than make it again (it would be left behind).
  fs::create_directory(dir / "depth", ec);
  if (!ec) fs::create_directory(dir / "rgb", ec);
  if (ec) throw Error(folder + ": cannot create the output folders (" + ec.message() + ")");

  const int total = options.max_frames >= 0 ? std::min(options.max_frames, source.size())
                                            : source.size();
  std::vector<FrameRecord> records(size_t(std::max(total, 0)));
  std::mutex progress_mutex;
  int done = 0;
  tbb::parallel_for(0, total, [&](int i) {
    const RgbdFrame frame = source.load(i);
    FrameRecord& r = records[size_t(i)];
    r.timestamp = frame.timestamp;
    r.pose = frame.T_world_cam_given;
    const std::string stem = tumTimestampString(frame.timestamp);
    writeDepthPngOrNoReading(dir / "depth" / (stem + ".png"), frame.depth);
    if (!frame.color.empty()) {
      // TUM pairs colour and depth pixel for pixel: a larger colour image (iPhone) is averaged
      // down to the depth size.
      writeColorPng((dir / "rgb" / (stem + ".png")).string(),
                    resizeColorArea(frame.color, frame.depth.width(), frame.depth.height()));
      r.has_color = true;
    }
    if (options.progress) {
      std::lock_guard<std::mutex> lock(progress_mutex);
      options.progress(++done, total);
    }
  });
  for (int i = 1; i < total; ++i) {
    if (tumTimestampString(records[i].timestamp) == tumTimestampString(records[i - 1].timestamp))
      throw Error(folder + ": frames " + std::to_string(i - 1) + " and " + std::to_string(i) +
                  " share the timestamp " + tumTimestampString(records[i].timestamp) +
                  " and would overwrite each other's files");
  }

  const std::string description = source.description();
  std::ostringstream rgb, depth, gt;
  rgb << listHeader("color images", description);
  depth << listHeader("depth maps", description);
  gt << "# ground truth trajectory (camera-to-world, camera x right y down z forward)\n"
     << "# written by vdbfuse convert from " << description << "\n"
     << "# timestamp tx ty tz qx qy qz qw\n";
  TumWriteResult result;
  result.frames = total;
  for (const FrameRecord& r : records) {
    const std::string ts = tumTimestampString(r.timestamp);
    depth << ts << " depth/" << ts << ".png\n";
    if (r.has_color) rgb << ts << " rgb/" << ts << ".png\n";
    if (r.pose) {
      const Eigen::Quaterniond q(r.pose->linear());
      const Eigen::Vector3d t = r.pose->translation();
      char line[256];
      std::snprintf(line, sizeof line, "%s %.9f %.9f %.9f %.9f %.9f %.9f %.9f\n", ts.c_str(),
                    t.x(), t.y(), t.z(), q.x(), q.y(), q.z(), q.w());
      gt << line;
      ++result.poses;
    }
  }
  const Intrinsics k = source.depthIntrinsics();
  const Distortion d = source.depthDistortion();
  char calib[512];
  std::snprintf(calib, sizeof calib,
                "# %dx%d, depth registered to RGB; written by vdbfuse convert from %s\n"
                "# fx fy cx cy\n%.6f %.6f %.6f %.6f\n"
                "# OpenCV distortion k1 k2 p1 p2 k3\n%.6f %.6f %.6f %.6f %.6f\n"
                "# depth PNG: uint16, depth_m = value / 5000 ; 0 = invalid\n",
                k.width, k.height, description.substr(0, 200).c_str(), k.fx, k.fy, k.cx, k.cy,
                d.k1, d.k2, d.p1, d.p2, d.k3);
  writeFileAtomic((dir / "rgb.txt").string(), rgb.str());
  writeFileAtomic((dir / "depth.txt").string(), depth.str());
  if (result.poses) writeFileAtomic((dir / "groundtruth.txt").string(), gt.str());
  writeFileAtomic((dir / "camera_intrinsics.txt").string(), calib);
  output.commit();
  return result;
}

}  // namespace vf
