#pragma once
// The options of `vdbfuse reconstruct` and what they mean for a run: the fusion settings, the
// settings a checkpoint must match, and the outputs the run may write. reconstruct_command.cpp
// runs it.
#include <CLI/CLI.hpp>

#include <optional>
#include <string>

#include "app/open_source.h"
#include "core/class_table.h"
#include "slam/reconstruction.h"
#include "io/labeled_source.h"

namespace vf::app {

struct ReconstructOptions {
  std::string dataset, output, trajectory;
  std::string odometry;            // the first pass's trajectory too, before the loop closure
  std::string report_json;         // the run's figures (reconstruct_report.h's RunFigures)
  std::string frame_log;           // a CSV row per frame of the first pass (frame_log.h)
  std::string loop_closure = "on";
  std::optional<std::string> volume_size;  // gone: kept only to say so
  float voxel_size_m = VolumeSpec{}.voxel_size_m;
  float truncation_m = 0;  // 0 = 5 voxels
  float max_depth_m = MeasurementParams{}.max_depth_m;
  std::string fuse_depth = "filtered";  // or raw (IntegrationParams::integrate_filtered_depth)
  int max_frames = 0;
  std::string device = "auto", poses = "icp", intrinsics;
  SourceOptions source;
  std::string renders_dir, video;
  bool bench = false, verbose = false, quiet = false, force = false, resume = false;
  int checkpoint_every = 0;  // frames; 0 = checkpoints only when interrupted
  // Semantic fusion.
  std::string labels_dir, classes_file, dynamic_classes;  // classes: default labels_dir/classes.json
  std::optional<int> mask_dilation_px;
  std::string labels_missing = "skip", class_vote = "majority";
  uint32_t class_vote_seed = 0;

  std::string checkpoint() const { return output + ".checkpoint"; }
};

// Declares every option of the command on `cmd`, bound to `o`.
void addReconstructOptions(CLI::App& cmd, ReconstructOptions& o);

// The class table that goes with --labels: --classes, else DIR/classes.json.
ClassTable loadClassTable(const ReconstructOptions& o);

// What must not change between a run and its resumption; the checkpoint checks the camera and
// the volume itself.
RunSettings runSettings(const ReconstructOptions& o, const FrameSource& source, Device device);

// Refuses outputs that would overwrite (without --force), be an input, be missing a folder, or be
// named for another format, and removes temporaries a killed run left beside them.
void claimOutputs(const ReconstructOptions& o);

// The fusion settings the options ask for; `labeled` is the labelled source when --labels is given.
ReconstructionOptions fusionOptions(const ReconstructOptions& o, const LabeledFrameSource* labeled, bool photometric);

}  // namespace vf::app
