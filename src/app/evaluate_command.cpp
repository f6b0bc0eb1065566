// vdbfuse evaluate: trajectory accuracy against ground truth, numbers comparable with TUM's
// evaluate_ate.py / evaluate_rpe.py.
#include <cstdio>
#include <memory>
#include <string>

#include "app/command_registry.h"
#include "io/trajectory_io.h"
#include "io/trajectory_metrics.h"

namespace vf::app {
namespace {

struct EvaluateOptions {
  std::string trajectory;
  std::string groundtruth;
  int delta_frames = 1;
};

void printRow(const char* name, double value, const char* unit) {
  std::printf("  %-8s %10.3f %s\n", name, value, unit);
}

void runEvaluate(const EvaluateOptions& o) {
  const Trajectory estimate = readTumTrajectory(o.trajectory);
  const Trajectory ground_truth = readTumTrajectory(o.groundtruth);
  const AteResult ate = computeAte(estimate, ground_truth);
  const RpeResult rpe = computeRpe(estimate, ground_truth, o.delta_frames);

  std::printf("trajectory   %s (%zu poses)\n", o.trajectory.c_str(), estimate.size());
  std::printf("groundtruth  %s (%zu poses)\n\n", o.groundtruth.c_str(), ground_truth.size());
  std::printf("ATE, rigid alignment, %d pairs within %.2f s\n", ate.pairs, kTumMaxTimeDifference_s);
  printRow("rmse", ate.rmse_m * 100, "cm");
  printRow("mean", ate.mean_m * 100, "cm");
  printRow("median", ate.median_m * 100, "cm");
  printRow("max", ate.max_m * 100, "cm");
  std::printf("\nRPE, delta %d frame%s, %d pairs\n", rpe.delta_frames, rpe.delta_frames == 1 ? "" : "s", rpe.pairs);
  printRow("trans", rpe.trans_rmse_m * 100, "cm   (rmse)");
  printRow("rot", rpe.rot_rmse_deg, "deg  (rmse)");
}

void setup(CLI::App& root) {
  auto options = std::make_shared<EvaluateOptions>();
  CLI::App* cmd = root.add_subcommand(
      "evaluate", "Compare a trajectory with ground truth: ATE (TUM evaluate_ate.py) and RPE (evaluate_rpe.py)");
  cmd->add_option("--trajectory,-t", options->trajectory, "estimated trajectory, TUM format (timestamp tx ty tz qx qy qz qw)")
      ->required()
      ->check(CLI::ExistingFile);
  cmd->add_option("--groundtruth,-g", options->groundtruth, "ground-truth trajectory, TUM format (e.g. groundtruth.txt)")
      ->required()
      ->check(CLI::ExistingFile);
  cmd->add_option("--delta", options->delta_frames, "RPE frame distance")
      ->capture_default_str()
      ->check(CLI::Range(1, 1000000));
  cmd->callback([options] { runEvaluate(*options); });
}

}  // namespace

VF_REGISTER_COMMAND(50, setup);

}  // namespace vf::app
