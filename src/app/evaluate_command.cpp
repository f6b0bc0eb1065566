// vdbfuse evaluate: trajectory accuracy against ground truth, numbers comparable with TUM's
// evaluate_ate.py / evaluate_rpe.py; with --mesh, surface accuracy / completion / F-score against
// a reference mesh (app/mesh_evaluation.h).
#include <cstdio>
#include <filesystem>
#include <memory>
#include <optional>
#include <string>

#include "app/command_registry.h"
#include "app/usage_errors.h"
#include "app/mesh_evaluation.h"
#include "app/open_source.h"
#include "core/error.h"
#include "io/trajectory_io.h"
#include "io/trajectory_metrics.h"

namespace vf::app {
namespace {

struct EvaluateOptions {
  std::string trajectory;
  std::string groundtruth;
  int delta_frames = 1;
  MeshEvaluationOptions mesh;
};

void printRow(const char* name, double value, const char* unit) {
  std::printf("  %-8s %10.3f %s\n", name, value, unit);
}

void runTrajectoryEvaluation(const EvaluateOptions& o) {
  if (o.trajectory.empty()) throw Error("evaluate: give --trajectory traj.txt (or --mesh with --reference)");
  const std::string gt_path = !o.groundtruth.empty() ? o.groundtruth : o.mesh.dataset;
  if (gt_path.empty()) throw Error("evaluate: give --groundtruth (a TUM file or a dataset folder) or --dataset DIR");
  const Trajectory estimate = readTumTrajectory(o.trajectory);
  const Trajectory ground_truth = loadGroundTruth(gt_path, o.mesh.source);
  requireDistinctTimestamps(estimate, o.trajectory);
  requireDistinctTimestamps(ground_truth, gt_path);
  requirePlausiblePositions(estimate, o.trajectory);
  requirePlausiblePositions(ground_truth, gt_path);
  const AteResult ate = computeAte(estimate, ground_truth);
  // A short run (a few frames) still gets its ATE; the RPE then says why it has no figure.
  std::optional<RpeResult> rpe;
  std::string no_rpe;
  try {
    rpe = computeRpe(estimate, ground_truth, o.delta_frames);
  } catch (const Error& e) {
    no_rpe = e.what();
  }

  std::printf("trajectory   %s (%zu poses)\n", o.trajectory.c_str(), estimate.size());
  std::printf("groundtruth  %s (%zu poses)\n\n", gt_path.c_str(), ground_truth.size());
  std::printf("ATE, rigid alignment, %d pairs within %.2f s\n", ate.pairs, kTumMaxTimeDifference_s);
  printRow("rmse", ate.rmse_m * 100, "cm");
  printRow("mean", ate.mean_m * 100, "cm");
  printRow("median", ate.median_m * 100, "cm");
  printRow("max", ate.max_m * 100, "cm");
  if (!rpe) {
    std::printf("\nRPE: none (%s)\n", no_rpe.c_str());
    return;
  }
  std::printf("\nRPE, delta %d frame%s, %d pairs\n", rpe->delta_frames, rpe->delta_frames == 1 ? "" : "s", rpe->pairs);
  printRow("trans", rpe->trans_rmse_m * 100, "cm   (rmse)");
  printRow("rot", rpe->rot_rmse_deg, "deg  (rmse)");
}

void runEvaluate(EvaluateOptions o) {
  if (o.mesh.mesh.empty() != o.mesh.reference.empty())
    throw Error("evaluate: --mesh and --reference go together (the reconstruction and the ground-truth mesh)");
  if (o.mesh.mesh.empty()) return runTrajectoryEvaluation(o);
  o.mesh.trajectory = o.trajectory;
  o.mesh.groundtruth = o.groundtruth;
  runMeshEvaluation(o.mesh);
}

void setupEvaluateCommand(CLI::App& root) {
  auto options = std::make_shared<EvaluateOptions>();
  CLI::App* cmd = root.add_subcommand(
      "evaluate",
      "Compare a trajectory with ground truth: ATE (TUM evaluate_ate.py) and RPE (evaluate_rpe.py); with --mesh and "
      "--reference, a reconstruction with a ground-truth mesh: accuracy, completion, F-score (NICE-SLAM's protocol)");
  cmd->add_option("--trajectory,-t", options->trajectory,
                  "estimated trajectory, TUM format (timestamp tx ty tz qx qy qz qw); with --mesh it aligns the mesh "
                  "to the reference and, with --dataset, limits completion to what it saw")
      ->check(existingFile());
  cmd->add_option("--groundtruth,-g", options->groundtruth,
                  "ground-truth trajectory: a TUM file (e.g. groundtruth.txt) or a dataset folder with poses "
                  "(7-Scenes, Replica, ScanNet, Redwood, TUM)")
      ->check(existingPath());
  cmd->add_option("--dataset", options->mesh.dataset,
                  "the input folder: its poses are the ground truth unless --groundtruth is given, and its intrinsics "
                  "and depth tell which parts of the reference the trajectory saw")
      ->check(existingPath());
  cmd->add_option("--delta", options->delta_frames, "RPE frame distance")
      ->capture_default_str()
      ->check(inRange(1, 1000000));
  cmd->add_option("--mesh", options->mesh.mesh, "reconstructed mesh (PLY, e.g. from vdbfuse mesh)")->check(existingFile());
  cmd->add_option("--reference", options->mesh.reference, "ground-truth mesh (PLY)")->check(existingFile());
  cmd->add_option("--max-distance", options->mesh.threshold_m,
                  "metres: a point within this of the other surface counts for completion and the F-score")
      ->capture_default_str()
      ->check(inRange(1e-5, 10.0));
  cmd->add_option("--samples", options->mesh.samples, "points sampled on each mesh (area-weighted)")
      ->capture_default_str()
      ->check(inRange(1000, 100000000));
  cmd->add_option("--align", options->mesh.align,
                  "how the mesh is brought into the reference's frame with --trajectory and ground truth: ate (the "
                  "ATE's rigid alignment), first (first pose onto its ground truth), none, or auto (ate unless the "
                  "camera moved along a line)")
      ->capture_default_str()
      ->check(CLI::IsMember({"auto", "ate", "first", "none"}));
  cmd->add_option("--depth-range", options->mesh.depth_range,
                  "MIN,MAX metres a camera sees (for what the trajectory saw; default reconstruct's 0.2,4)");
  cmd->add_flag("--frustum-only", options->mesh.frustum_only,
                "count reference points in a camera's frustum as seen even when the frame's depth shows them hidden");
  cmd->add_option("--format", options->mesh.source.format, "format of --dataset / --groundtruth folders (default auto)");
  cmd->add_option("--depth-scale", options->mesh.source.depth_units_per_metre,
                  "depth units per metre of --dataset, overriding its own");
  cmd->callback([options] { runEvaluate(*options); });
}

}  // namespace

VF_REGISTER_COMMAND(50, setupEvaluateCommand);

}  // namespace vf::app
