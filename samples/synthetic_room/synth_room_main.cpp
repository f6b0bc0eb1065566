// vdbfuse-synth-room: writes a synthetic scan (the room, or the ring corridor with --scene
// corridor, and their stress variants) as a TUM RGB-D folder with its ground-truth mesh, or
// scores a reconstruction of it (completion of the seen surface, accuracy).
#include <CLI/CLI.hpp>

#include <algorithm>
#include <atomic>
#include <chrono>
#include <cstdio>
#include <filesystem>
#include <mutex>
#include <string>
#include <system_error>
#include <vector>

#include "app/usage_errors.h"
#include "core/atomic_output.h"
#include "core/error.h"
#include "core/output_lock.h"
#include "core/pose.h"
#include "io/mesh_io.h"
#include "io/trajectory_io.h"
#include "io/tum_writer.h"
#include "corridor_geometry.h"
#include "corridor_path.h"
#include "room_evaluation.h"
#include "room_mesh.h"
#include "room_source.h"
#include "view_conditioning.h"

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
    if (inner_.blank(inner_.walkIndex(index))) return frame;  // a covered lens is meant to have nothing
    for (int y = 0; y < frame.depth.height(); ++y)
      for (int x = 0; x < frame.depth.width(); ++x) in_range += frame.depth(x, y) >= 0.4f && frame.depth(x, y) <= 4.f;
    const double share = double(in_range) / double(frame.depth.width() * frame.depth.height());
    std::lock_guard<std::mutex> lock(mutex_);
    if (share < min_share_) {
      min_share_ = share;
      min_frame_ = inner_.walkIndex(index);  // frames are named by their walk index, as the runs are
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
  std::string scene = "room", depth_model;  // depth_model empty: the scene's
  int frames = 0;                            // 0: the scene's
  uint64_t seed = 1, walk = 0;
  bool force = false, no_noise = false;
  std::vector<std::string> gaps, blanks;
  std::string close_wall;
  float threshold_m = 0.03f, spacing_m = 0.01f;
};

// The scan the options name: the scene's defaults, then what was given. The evaluation builds
// the same one, so it sees the scene through the frames that were written.
RoomScanOptions scanOptions(const Options& o) {
  RoomScanOptions scan = scanDefaults(parseScene(o.scene));
  if (o.frames > 0) scan.frames = o.frames;
  scan.seed = o.seed;
  scan.walk = o.walk;
  if (o.depth_model == "tum") scan.sensor = SensorModel{};
  if (o.depth_model == "kinect-v1") scan.sensor = kinectV1Sensor();
  scan.sensor.noise = !o.no_noise;
  parseSize(o.size, scan.width, scan.height);
  for (const std::string& g : o.gaps) scan.gaps.push_back(parseFrameRange(g, "--gap"));
  for (const std::string& b : o.blanks) scan.blanks.push_back(parseFrameRange(b, "--blank"));
  if (!o.close_wall.empty()) scan.close_wall = parseFrameRange(o.close_wall, "--close-wall");
  return scan;
}

// Runs of consecutive frame indices as "a-b, c, d-e".
std::string runsText(const std::vector<int>& frames) {
  std::string text;
  for (size_t i = 0; i < frames.size();) {
    size_t j = i;
    while (j + 1 < frames.size() && frames[j + 1] == frames[j] + 1) ++j;
    if (!text.empty()) text += ", ";
    text += std::to_string(frames[i]) + (j > i ? "-" + std::to_string(frames[j]) : "");
    i = j + 1;
  }
  return text.empty() ? "none" : text;
}

// Where each gap makes the camera jump, and which frames are blank.
void reportRuns(const RoomScanSource& source) {
  const RoomScanOptions& o = source.options();
  const Trajectory& walk = source.walk();
  for (const FrameRange& g : o.gaps) {
    const Pose& a = walk[size_t(std::max(0, g.from - 1))].T_world_cam;
    const Pose& b = walk[size_t(std::min(o.frames - 1, g.end()))].T_world_cam;
    std::printf("gap          frames %d-%d left out: the camera jumps %.2f m and %.1f deg (t %.3f -> %.3f s)\n", g.from,
                g.end() - 1, (b.translation() - a.translation()).norm(),
                rotationDeg(a.inverse() * b),
                walk[size_t(std::max(0, g.from - 1))].timestamp, walk[size_t(std::min(o.frames - 1, g.end()))].timestamp);
  }
  for (const FrameRange& b : o.blanks)
    std::printf("blank        frames %d-%d written with no depth and black colour (a covered lens)\n", b.from, b.end() - 1);
}

// Which frames leave point-to-plane ICP a direction it cannot pin down (rendered at 80x60), and
// which frames of a close-wall run see the wall alone.
void reportViews(const RoomScanSource& source) {
  const RoomScanOptions& o = source.options();
  const Trajectory& walk = source.walk();
  const Intrinsics small = kinectIntrinsics(80, 60);
  std::vector<int> weak_one, weak_three, wall_only;
  int with_depth = 0;
  for (int w = 0; w < source.size(); ++w) {
    const int i = source.walkIndex(w);
    if (source.blank(i)) continue;
    ++with_depth;
    const CleanView view = renderClean(source.room(), small, walk[size_t(i)].T_world_cam);
    const int weak = weakDirections(icpConditioning(source.room(), view, small, walk[size_t(i)].T_world_cam));
    if (weak >= 1) weak_one.push_back(i);
    if (weak >= 3) weak_three.push_back(i);
    if (o.close_wall && o.close_wall->contains(i)) {
      bool one = true;
      for (size_t p = 0; p < view.primitive.size(); ++p) one = one && view.primitive[p] == view.primitive[0];
      if (one && view.primitive[0] >= 0) wall_only.push_back(i);
    }
  }
  if (o.close_wall)
    std::printf("close wall   frames %d-%d turn to the outer wall at %.1f m; frames %s see nothing else\n", o.close_wall->from,
                o.close_wall->end() - 1, kCloseWallDistance_m, runsText(wall_only).c_str());
  std::printf("weak views   %zu of the %d frames with depth leave ICP a direction below 1e-3 of the strongest: %s\n",
              weak_one.size(), with_depth, runsText(weak_one).c_str());
  std::printf("             %zu leave three (one plane in view): %s\n", weak_three.size(), runsText(weak_three).c_str());
}

void generate(const Options& o) {
  const RoomScanOptions scan = scanOptions(o);
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
  // The sweep of what a killed earlier run left beside it is allowed only under the output's
  // lock (core/output_lock.h): without it every scan failed to start.
  lockOutputForThisRun(target.string());
  removeStaleTemporaries(target.string());
  const auto t0 = std::chrono::steady_clock::now();
  const TriangleMesh mesh = groundTruthMesh(source.room());
  AtomicFolder folder(target.string());
  const TumWriteResult written = writeTumFolder(counting, folder.tempPath());
  writePly(mesh, folder.file("groundtruth_mesh.ply"), false);
  folder.commit();
  const double frames_s = secondsSince(t0);
  const std::string mesh_path = (target / "groundtruth_mesh.ply").string();

  const PathStats path = pathStats(source.walk());
  const Intrinsics k = source.depthIntrinsics();
  const bool corridor = scan.scene == Scene::kCorridor;
  if (corridor)
    std::printf("corridor     ring %.1f x %.1f x %.1f m round a %.0f x %.0f m block, %.0f m wide, %zu primitives\n",
                CorridorLayout::kOuterX_m, CorridorLayout::kOuterY_m, CorridorLayout::kHeight_m,
                CorridorLayout::kBlockX1_m - CorridorLayout::kBlockX0_m, CorridorLayout::kBlockY1_m - CorridorLayout::kBlockY0_m,
                CorridorLayout::kWidth_m, source.room().primitives.size());
  else
    std::printf("room         8.0 x 6.0 x 2.6 m, %zu primitives (shell, wall slabs, furniture)\n",
                source.room().primitives.size());
  const char* sensor = !scan.sensor.noise                   ? ", no noise"
                       : scan.sensor.disparity_step_per_m > 0 ? ", Kinect v1 depth (disparity steps, per-pixel bias)"
                                                            : ", Kinect v1 noise";
  std::printf("camera       %dx%d, fx %.1f fy %.1f cx %.1f cy %.1f, %d frames at %.0f Hz, seed %llu%s\n", k.width,
              k.height, k.fx, k.fy, k.cx, k.cy, written.frames, kFrameRateHz, (unsigned long long)o.seed, sensor);
  std::printf("path         %.2f m, turn %.1f deg, speed <= %.2f m/s, turn rate <= %.1f deg/s, height %.2f-%.2f m\n",
              path.length_m, path.turn_deg, path.max_speed_m_s, path.max_turn_rate_deg_s, path.min_height_m,
              path.max_height_m);
  if (corridor) {
    std::printf("loop         %.2f m round the centre line, back at the start after %.1f s (frame %d): %.2f loops walked\n",
                corridorLoopLength_m(), corridorLoopTime_s(), int(std::lround(corridorLoopTime_s() * kFrameRateHz)),
                path.length_m / corridorLoopLength_m());
    reportViews(source);
  }
  reportRuns(source);
  std::printf("depth        every frame%s has >= %.1f %% of its pixels at 0.4-4 m (fewest: frame %d)\n",
              scan.blanks.empty() ? "" : " but the blank ones", 100.0 * counting.minShare(), counting.minFrame());
  std::printf("wrote        %s: rgb/ depth/ rgb.txt depth.txt groundtruth.txt (%d poses) camera_intrinsics.txt, in %.1f s\n",
              target.string().c_str(), written.poses, frames_s);
  std::printf("wrote        %s (%zu vertices, %zu triangles, the %s's frame as groundtruth.txt)\n", mesh_path.c_str(),
              mesh.vertexCount(), mesh.triangleCount(), sceneName(scan.scene).c_str());
}

void evaluate(const Options& o) {
  const RoomScanSource source(scanOptions(o));
  const int width = source.options().width, height = source.options().height;
  const auto t0 = std::chrono::steady_clock::now();
  const Room& room = source.room();
  const SurfaceSamples samples = sampleSurface(room, o.spacing_m);
  const Trajectory path = source.groundTruth();        // what the reconstruction's poses are aligned to
  const Trajectory saw = source.depthPoses();          // what saw the scene (no gaps, no blanks)
  const std::vector<uint8_t> seen = markSeen(room, samples, saw, kinectIntrinsics(width, height));

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
                t.norm(), rotationDeg(T));
  }
  std::printf("seen surface    %zu of %zu samples (%.1f m^2 at %.0f mm spacing) by %zu frames at %dx%d (%s)\n", s.seen,
              s.samples, double(s.seen) * cell_area, 1000.0 * o.spacing_m, saw.size(), width, height,
              source.description().c_str());
  std::printf("completion      %.2f %% of the seen surface within %.0f mm\n", 100.0 * s.completion, 1000.0 * s.threshold_m);
  std::printf("accuracy        mean %.2f mm, median %.2f mm, 90th percentile %.2f mm over %zu vertices; %.2f %% within %.0f mm\n",
              1000.0 * s.accuracy_mean_m, 1000.0 * s.accuracy_median_m, 1000.0 * s.accuracy_p90_m, s.vertices,
              100.0 * s.precision, 1000.0 * s.threshold_m);
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
  CLI::App app{"vdbfuse-synth-room: a synthetic RGB-D scan with a known surface and known poses (an 8 x 6 x 2.6 m "
               "room, or a 38 m walk round a ring corridor), written as a TUM folder; or, with --evaluate, the completion and "
               "accuracy of a reconstruction of it (give the same scan options as when it was written)"};
  Options o;
  app.add_option("output", o.output, "folder to write (TUM layout, plus groundtruth_mesh.ply)");
  app.add_option("--scene", o.scene, "room (8 x 6 m, a full turn) or corridor (a 38 m walk 1.17 times round a 32 m ring corridor)")
      ->capture_default_str()
      ->check(CLI::IsMember({"room", "corridor"}));
  app.add_option("--frames", o.frames, "frames of the 30 Hz walk (default: the room 300, one full turn and 10 degrees; "
                                       "the corridor 1200, 38 m)")
      ->check(CLI::Range(1, 100000));
  // Both are unsigned, and CLI11 would take -1 as 2^64 - 1: a number, but not the one meant.
  app.add_option("--seed", o.seed, "seed of the sensor noise")->capture_default_str()->check(vf::app::atLeast(0));
  app.add_option("--walk", o.walk,
                 "corridor: 0 the default walk; another number carries the camera differently along the same path "
                 "(other phases of its swing and weave, its looks at a side wall at other times)")
      ->capture_default_str()
      ->check(vf::app::atLeast(0));
  app.add_option("--size", o.size, "image size WIDTHxHEIGHT (the Kinect's view scaled)")->capture_default_str();
  app.add_option("--depth-model", o.depth_model,
                 "tum: noise sigma(z), 1/5000 m steps (the room's default); kinect-v1: the same noise, rounded to "
                 "disparity steps of 2.85e-3 z^2 m, with a fixed per-pixel bias of a few mm/m (the corridor's default)")
      ->check(CLI::IsMember({"tum", "kinect-v1"}));
  app.add_option("--gap", o.gaps, "FROM:COUNT: leave walk frames FROM..FROM+COUNT-1 out (the camera jumps); repeatable")
      ->expected(1)
      ->take_all();
  app.add_option("--blank", o.blanks,
                 "FROM:COUNT: write those walk frames with zero depth and black colour (a covered lens); repeatable")
      ->expected(1)
      ->take_all();
  app.add_option("--close-wall", o.close_wall,
                 "FROM:COUNT (corridor): in those frames turn to the outer wall and step to 0.7 m from it, so that "
                 "the middle of the run sees one plain wall only (e.g. 510:150 on the north leg's plain stretch)");
  app.add_flag("-f,--force", o.force, "replace an existing output folder, with everything in it");
  app.add_flag("--no-noise", o.no_noise, "a perfect sensor: exact depth everywhere, exact colour");
  app.add_option("--evaluate", o.evaluate, "score this reconstructed mesh (PLY) instead of writing the scan")
      ->check(vf::app::existingFile());
  app.add_option("--trajectory", o.trajectory,
                 "with --evaluate: the reconstruction's trajectory (TUM), to bring the mesh into the scene's frame")
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
