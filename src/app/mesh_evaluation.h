#pragma once
// vdbfuse evaluate --mesh REC.ply --reference GT.ply: surface accuracy, completion and F-score
// (io/mesh_metrics.h) after bringing the reconstruction into the reference's frame by the
// trajectory and its ground truth (io/trajectory_alignment.h).
#include <string>

#include "app/open_source.h"
#include "core/pose.h"

namespace vf::app {

struct MeshEvaluationOptions {
  std::string mesh, reference;
  std::string trajectory;   // optional: alignment and, with dataset, what was seen
  std::string groundtruth;  // optional: TUM file or dataset folder; else the dataset's poses
  std::string dataset;      // optional: intrinsics, depth and poses of the input
  SourceOptions source;     // how the dataset is opened
  double threshold_m = 0.05;
  size_t samples = 1000000;
  std::string align = "auto";
  std::string depth_range;  // "MIN,MAX"; empty: MeasurementParams' range
  bool frustum_only = false;
};

// Prints the alignment applied, then `accuracy`, `completion` and `F-score@..` lines.
void runMeshEvaluation(const MeshEvaluationOptions& options);

// Poses from a TUM trajectory file, or the ground truth of a dataset folder (any readable
// layout); throws vf::Error when there are none.
Trajectory loadGroundTruth(const std::string& path, const SourceOptions& source);

}  // namespace vf::app
