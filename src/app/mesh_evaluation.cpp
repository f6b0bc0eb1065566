#include "app/mesh_evaluation.h"

#include <chrono>
#include <cmath>
#include <cstdio>
#include <filesystem>
#include <sstream>

#include "core/error.h"
#include "fusion/params.h"
#include "io/mesh_io.h"
#include "io/mesh_metrics.h"
#include "io/trajectory_alignment.h"
#include "io/trajectory_io.h"
#include "io/trajectory_metrics.h"
#include "io/triangle_bvh.h"

namespace vf::app {
namespace {

std::pair<float, float> parseDepthRange(const std::string& text) {
  MeasurementParams defaults;
  if (text.empty()) return {defaults.min_depth_m, defaults.max_depth_m};
  std::istringstream in(text);
  float lo = 0, hi = 0;
  char comma = 0;
  if (!(in >> lo >> comma >> hi) || comma != ',' || !(in >> std::ws).eof() || !(lo >= 0 && hi > lo))
    throw Error("--depth-range " + text + ": expected MIN,MAX in metres with 0 <= MIN < MAX, e.g. 0.2,4");
  return {lo, hi};
}

std::string cm(double m) {
  char text[32];
  std::snprintf(text, sizeof text, "%.3f cm", m * 100);
  return text;
}

// Marks the reference points some frame of the dataset saw from its trajectory pose; returns
// the number of frames used.
int markSeenByTrajectory(const std::vector<Vec3f>& points, const FrameSource& source, const Trajectory& estimate,
                         const Pose& T_ref_est, const MeshEvaluationOptions& o, std::vector<uint8_t>& seen) {
  const auto [min_depth, max_depth] = parseDepthRange(o.depth_range);
  int used = 0;
  for (int i = 0; i < source.size(); ++i) {
    const RgbdFrame frame = source.load(i);
    const std::optional<Pose> pose = poseNearTimestamp(estimate, frame.timestamp);
    if (!pose) continue;
    ViewCamera camera;
    camera.T_world_cam = T_ref_est * *pose;
    camera.intrinsics = source.depthIntrinsics();
    camera.min_depth_m = min_depth;
    camera.max_depth_m = max_depth;
    camera.depth = o.frustum_only ? nullptr : &frame.depth;
    camera.occlusion_tolerance_m = float(o.threshold_m);
    markSeen(points, camera, seen);
    ++used;
  }
  if (used == 0)
    throw Error(o.trajectory + ": no pose at the timestamp of any frame of " + o.dataset +
                " (is it the trajectory reconstruct wrote for this dataset?)");
  return used;
}

}  // namespace

Trajectory loadGroundTruth(const std::string& path, const SourceOptions& source) {
  Trajectory gt;
  // A dataset folder, or a Record3D capture (.r3d): the poses it carries.
  if (std::filesystem::is_directory(path) || std::filesystem::path(path).extension() == ".r3d") {
    gt = openFrameSource(path, source)->groundTruth();
    if (gt.empty()) throw Error(path + ": the dataset has no poses to compare against");
  } else {
    gt = readTumTrajectory(path);
  }
  return gt;
}

void runMeshEvaluation(const MeshEvaluationOptions& o) {
  const auto start = std::chrono::steady_clock::now();
  // A z-up or y-up export (vdbfuse's default for PLY) is compared in the scene's frame, the
  // trajectory's: scored as written, it would lie metres off and score near zero. So is a
  // reference that vdbfuse wrote (another run's mesh), so that two exports still compare.
  std::string frame_note, reference_frame_note;
  const TriangleMesh reference = readPlyInSceneFrame(o.reference, &reference_frame_note);
  TriangleMesh reconstruction = readPlyInSceneFrame(o.mesh, &frame_note);

  Trajectory estimate;
  TrajectoryAlignment alignment;
  alignment.description = "none (no --trajectory: the mesh is taken to be in the reference's frame)";
  if (!o.trajectory.empty()) {
    estimate = readTumTrajectory(o.trajectory);
    requirePlausiblePositions(estimate, o.trajectory);
    const std::string gt_path = !o.groundtruth.empty() ? o.groundtruth : o.dataset;
    if (!gt_path.empty()) {
      const Trajectory ground_truth = loadGroundTruth(gt_path, o.source);
      requirePlausiblePositions(ground_truth, gt_path);
      alignment = alignTrajectory(estimate, ground_truth, parseAlignmentMethod(o.align));
    } else {
      alignment.description = "none (no --groundtruth or --dataset: the trajectory is taken to be in the reference's frame)";
    }
  }
  reconstruction = transformMesh(reconstruction, alignment.T_gt_est);

  // Which file has nothing to sample (no triangle, or none with an area) is what the user needs.
  const auto sampled = [&o](const TriangleMesh& mesh, uint64_t seed, const std::string& path) {
    try {
      return sampleSurface(mesh, o.samples, seed);
    } catch (const Error& e) {
      throw Error(path + ": " + e.what());
    }
  };
  const std::vector<Vec3f> rec_points = sampled(reconstruction, 1, o.mesh);
  std::vector<Vec3f> ref_points = sampled(reference, 2, o.reference);
  const size_t ref_sampled = ref_points.size();
  std::string seen_note = "all of it (give --trajectory and --dataset to count only what the cameras saw)";
  if (!estimate.empty() && !o.dataset.empty()) {
    std::vector<uint8_t> seen(ref_points.size(), 0);
    const int frames = markSeenByTrajectory(ref_points, *openFrameSource(o.dataset, o.source), estimate,
                                            alignment.T_gt_est, o, seen);
    std::vector<Vec3f> kept;
    for (size_t i = 0; i < ref_points.size(); ++i)
      if (seen[i]) kept.push_back(ref_points[i]);
    ref_points = std::move(kept);
    seen_note = std::to_string(ref_points.size()) + " of " + std::to_string(ref_sampled) + " points seen by " +
                std::to_string(frames) + " frames" + (o.frustum_only ? " (frustum only)" : " (frustum and depth)");
  }

  const TriangleBvh ref_surface(reference), rec_surface(reconstruction);
  const SurfaceMetrics m =
      surfaceMetrics(ref_surface.distances(rec_points), rec_surface.distances(ref_points), o.threshold_m);
  // A figure that is not finite is no result (a mesh whose coordinates overflow on the way).
  for (const double v : {m.accuracy_median_m, m.accuracy_mean_m, m.completion_median_m, m.completion_mean_m, m.fscore})
    if (!std::isfinite(v))
      throw Error(o.mesh + " against " + o.reference +
                  ": the distances are not finite (coordinates too large to compare, or no point near the other "
                  "surface)");
  const double seconds = std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();

  std::printf("reconstruction  %s (%zu triangles, %zu points sampled; %s)\n", o.mesh.c_str(),
              reconstruction.triangleCount(), rec_points.size(), frame_note.c_str());
  std::printf("reference       %s (%zu triangles; completion over %s; %s)\n", o.reference.c_str(),
              reference.triangleCount(), seen_note.c_str(), reference_frame_note.c_str());
  std::printf("alignment       %s\n\n", alignment.description.c_str());
  char label[32];
  std::snprintf(label, sizeof label, "F-score@%gcm", o.threshold_m * 100);
  std::printf("accuracy     %s median, %s mean (reconstruction to reference surface)\n", cm(m.accuracy_median_m).c_str(),
              cm(m.accuracy_mean_m).c_str());
  std::printf("completion   %.2f %% of reference points within %g cm (median %s, mean %s)\n",
              m.completion_ratio * 100, o.threshold_m * 100, cm(m.completion_median_m).c_str(),
              cm(m.completion_mean_m).c_str());
  std::printf("%-12s %.4f (precision %.2f %%, recall %.2f %%)\n", label, m.fscore, m.precision * 100,
              m.completion_ratio * 100);
  std::fflush(stdout);
  std::fprintf(stderr, "evaluated in %.2f s\n", seconds);
}

}  // namespace vf::app
