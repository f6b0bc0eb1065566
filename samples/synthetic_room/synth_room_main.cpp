// vdbfuse-synth-room: writes the synthetic room scan as a TUM RGB-D folder with its ground-truth
// mesh, or scores a reconstruction of it (completion of the seen surface, accuracy).
#include <CLI/CLI.hpp>

#include <algorithm>
#include <atomic>
#include <chrono>
#include <cstdio>
#include <filesystem>
#include <mutex>
#include <string>
#include <system_error>

#include "app/usage_errors.h"
#include "core/atomic_output.h"
#include "core/error.h"
#include "io/mesh_io.h"
#include "io/trajectory_io.h"
#include "io/tum_writer.h"
#include "room_evaluation.h"
#include "room_mesh.h"
#include "room_source.h"

namespace {

using namespace vf;
using namespace vf::synth;
namespace fs = std::filesystem;

double secondsSince(std::chrono::steady_clock::time_point t0) {
  return std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count();
}

void parseSize(const std::string& text, int& width, int& height) {
  char x = 0;
  int w = 0, h = 0;
  if (std::sscanf(text.c_str(), "%d%c%d", &w, &x, &h) != 3 || x != 'x')
    throw Error("--size '" + text + "': expected WIDTHxHEIGHT, e.g. 640x480");
  width = w;
  height = h;
}

// Forwards frames and keeps the smallest share of pixels with depth in the fusion's range, so
// the report can say that every frame had enough to track.
class RangeCountingSource : public FrameSource {
 public:
  explicit RangeCountingSource(const RoomScanSource& inner) : inner_(inner) {}
  int size() const override { return inner_.size(); }
  Intrinsics depthIntrinsics() const override { return inner_.depthIntrinsics(); }
  std::string description() const override { return inner_.description(); }
  Trajectory groundTruth() const override { return inner_.groundTruth(); }
  RgbdFrame load(int index) const override {
    RgbdFrame frame = inner_.load(index);
    size_t in_range = 0;
    for (int y = 0; y < frame.depth.height(); ++y)
      for (int x = 0; x < frame.depth.width(); ++x) in_range += frame.depth(x, y) >= 0.4f && frame.depth(x, y) <= 4.f;
    const double share = double(in_range) / double(frame.depth.width() * frame.depth.height());
    std::lock_guard<std::mutex> lock(mutex_);
    if (share < min_share_) {
      min_share_ = share;
      min_frame_ = index;
    }
    return frame;
  }
  double minShare() const { return min_share_; }
  int minFrame() const { return min_frame_; }

 private:
  const RoomScanSource& inner_;
  mutable std::mutex mutex_;
  mutable double min_share_ = 1.0;
  mutable int min_frame_ = -1;
};

struct Options {
  std::string output, evaluate, trajectory, align = "ate", size = "640x480";
  int frames = kDefaultFrames;
  uint64_t seed = 1;
  bool force = false, no_noise = false;
  float threshold_m = 0.03f, spacing_m = 0.01f;
};

void generate(const Options& o) {
  RoomScanOptions scan;
  scan.frames = o.frames;
  scan.seed = o.seed;
  scan.sensor.noise = !o.no_noise;
  parseSize(o.size, scan.width, scan.height);
  const RoomScanSource source(scan);
  const RangeCountingSource counting(source);

  // The scan and its mesh go into a temporary folder renamed into place when both are written
  // (core/atomic_output.h): an error or Ctrl-C leaves no half-written scan, and an existing one
  // is replaced only with --force.
  fs::path target(o.output);
  if (!target.has_filename()) target = target.parent_path();  // "room/"
  if (fs::exists(target) && !o.force) throw Error(target.string() + ": exists (use --force to replace it)");
  std::error_code ec;
  if (target.has_parent_path()) fs::create_directories(target.parent_path(), ec);
  if (ec) throw Error(target.string() + ": cannot create the folder it goes in (" + ec.message() + ")");
  removeStaleTemporaries(target.string());  // what a killed earlier run left beside it
  const auto t0 = std::chrono::steady_clock::now();
  const TriangleMesh mesh = groundTruthMesh(source.room());
  AtomicFolder folder(target.string());
  const TumWriteResult written = writeTumFolder(counting, folder.tempPath());
  writePly(mesh, folder.file("groundtruth_mesh.ply"), false);
  folder.commit();
  const double frames_s = secondsSince(t0);
  const std::string mesh_path = (target / "groundtruth_mesh.ply").string();

  const PathStats path = pathStats(source.groundTruth());
  const Intrinsics k = source.depthIntrinsics();
  std::printf("room         8.0 x 6.0 x 2.6 m, %zu primitives (shell, wall slabs, furniture)\n",
              source.room().primitives.size());
  std::printf("camera       %dx%d, fx %.1f fy %.1f cx %.1f cy %.1f, %d frames at %.0f Hz, seed %llu%s\n", k.width,
              k.height, k.fx, k.fy, k.cx, k.cy, written.frames, kFrameRateHz, (unsigned long long)o.seed,
              o.no_noise ? ", no noise" : ", Kinect v1 noise");
  std::printf("path         %.2f m, turn %.1f deg, speed <= %.2f m/s, turn rate <= %.1f deg/s, height %.2f-%.2f m\n",
              path.length_m, path.turn_deg, path.max_speed_m_s, path.max_turn_rate_deg_s, path.min_height_m,
              path.max_height_m);
  std::printf("depth        every frame has >= %.1f %% of its pixels at 0.4-4 m (fewest: frame %d)\n",
              100.0 * counting.minShare(), counting.minFrame());
  std::printf("wrote        %s: rgb/ depth/ rgb.txt depth.txt groundtruth.txt (%d poses) camera_intrinsics.txt, in %.1f s\n",
              target.string().c_str(), written.poses, frames_s);
  std::printf("wrote        %s (%zu vertices, %zu triangles, the room's frame as groundtruth.txt)\n", mesh_path.c_str(),
              mesh.vertexCount(), mesh.triangleCount());
}

void evaluate(const Options& o) {
  int width = 0, height = 0;
  parseSize(o.size, width, height);
  const auto t0 = std::chrono::steady_clock::now();
  const Room room = makeRoom();
  const SurfaceSamples samples = sampleSurface(room, o.spacing_m);
  const Trajectory path = cameraPath(o.frames);
  const std::vector<uint8_t> seen = markSeen(room, samples, path, kinectIntrinsics(width, height));

  std::string frame_note;  // scored as written, a z-up export would lie metres off
  TriangleMesh mesh = readPlyInSceneFrame(o.evaluate, &frame_note);
  Pose T = Pose::Identity();
  if (!o.trajectory.empty()) {
    T = alignTo(readTumTrajectory(o.trajectory), path, parseAlignment(o.align));
    mesh = transformed(mesh, T);
  }
  const SurfaceScores s = scoreReconstruction(room, samples, seen, mesh, o.threshold_m);
  const double cell_area = double(o.spacing_m) * double(o.spacing_m);
  std::printf("reconstruction  %s (%zu vertices, %zu triangles; %s)\n", o.evaluate.c_str(), mesh.vertexCount(),
              mesh.triangleCount(), frame_note.c_str());
  if (o.trajectory.empty()) {
    std::printf("alignment       none (the mesh is taken to be in the room's frame; give --trajectory to align)\n");
  } else {
    const Eigen::Vector3d t = T.translation();
    std::printf("alignment       %s from %s: |t| %.3f m, rotation %.2f deg\n", o.align.c_str(), o.trajectory.c_str(),
                t.norm(), Eigen::AngleAxisd(T.linear()).angle() * 180.0 / M_PI);
  }
  std::printf("seen surface    %zu of %zu samples (%.1f m^2 at %.0f mm spacing) by %d frames at %dx%d\n", s.seen,
              s.samples, double(s.seen) * cell_area, 1000.0 * o.spacing_m, o.frames, width, height);
  std::printf("completion      %.2f %% of the seen surface within %.0f mm\n", 100.0 * s.completion, 1000.0 * s.threshold_m);
  std::printf("accuracy        mean %.2f mm, median %.2f mm over %zu vertices; %.2f %% within %.0f mm\n",
              1000.0 * s.accuracy_mean_m, 1000.0 * s.accuracy_median_m, s.vertices, 100.0 * s.precision,
              1000.0 * s.threshold_m);
  std::printf("F-score         %.2f %%\n", 100.0 * s.fscore);
  // Which parts are missing most (by seen area not reconstructed).
  std::vector<size_t> order(room.primitives.size());
  for (size_t i = 0; i < order.size(); ++i) order[i] = i;
  auto missing = [&](size_t i) { return s.by_primitive[i].first - s.by_primitive[i].second; };
  std::sort(order.begin(), order.end(), [&](size_t a, size_t b) { return missing(a) > missing(b); });
  std::printf("most missing   ");
  if (s.complete == s.seen) std::printf(" nothing");
  for (size_t j = 0; j < std::min<size_t>(5, order.size()) && missing(order[j]) > 0; ++j)
    std::printf(" %s %.2f m^2 (%.1f %% of it);", room.primitives[order[j]].name.c_str(), double(missing(order[j])) * cell_area,
                100.0 * double(missing(order[j])) / double(s.by_primitive[order[j]].first));
  std::printf("\nevaluated in %.1f s\n", secondsSince(t0));
}

}  // namespace

int main(int argc, char** argv) {
  CLI::App app{"vdbfuse-synth-room: a synthetic RGB-D scan of an 8 x 6 x 2.6 m room with a known surface, "
               "written as a TUM folder; or, with --evaluate, the completion and accuracy of a reconstruction of it"};
  Options o;
  app.add_option("output", o.output, "folder to write (TUM layout, plus groundtruth_mesh.ply)");
  app.add_option("--frames", o.frames, "frames of the 30 Hz path (300: one full turn and 10 degrees)")
      ->capture_default_str()
      ->check(CLI::Range(1, 100000));
  app.add_option("--seed", o.seed, "seed of the sensor noise")->capture_default_str();
  app.add_option("--size", o.size, "image size WIDTHxHEIGHT (the Kinect's view scaled)")->capture_default_str();
  app.add_flag("-f,--force", o.force, "replace an existing output folder, with everything in it");
  app.add_flag("--no-noise", o.no_noise, "a perfect sensor: exact depth everywhere, exact colour");
  app.add_option("--evaluate", o.evaluate, "score this reconstructed mesh (PLY) instead of writing the scan")
      ->check(vf::app::existingFile());
  app.add_option("--trajectory", o.trajectory,
                 "with --evaluate: the reconstruction's trajectory (TUM), to bring the mesh into the room's frame")
      ->check(vf::app::existingFile());
  app.add_option("--align", o.align, "with --trajectory: ate (the ATE's rigid alignment), first or none")
      ->capture_default_str()
      ->check(CLI::IsMember({"ate", "first", "none"}));
  app.add_option("--threshold-m", o.threshold_m, "completion / precision distance")
      ->capture_default_str()
      ->check(CLI::Range(0.001f, 1.f));
  app.add_option("--spacing-m", o.spacing_m, "spacing of the ground-truth surface samples")
      ->capture_default_str()
      ->check(CLI::Range(0.002f, 0.5f));
  try {
    app.parse(argc, argv);
  } catch (const CLI::ParseError& e) {
    return vf::app::reportParseError(app, e, "vdbfuse-synth-room");
  }
  try {
    if (!o.evaluate.empty()) {
      evaluate(o);
    } else if (!o.output.empty()) {
      generate(o);
    } else {
      std::fprintf(stderr, "vdbfuse-synth-room: give an output folder, or --evaluate mesh.ply\n%s", app.help().c_str());
      return 1;
    }
  } catch (const vf::Error& e) {
    std::fprintf(stderr, "vdbfuse-synth-room: error: %s\n", e.what());
    return 1;
  } catch (const std::exception& e) {
    std::fprintf(stderr, "vdbfuse-synth-room: internal error: %s\n", e.what());
    return 2;
  }
  return 0;
}
