// vdbfuse reconstruct DATASET -o scene.vdb: parses the options, runs a Reconstruction
// (slam/reconstruction.h) and writes the scene, the trajectory and, when asked or interrupted,
// a checkpoint to resume from.
#include <chrono>
#include <cstdio>
#include <filesystem>
#include <map>
#include <memory>
#include <optional>

#include "app/command_registry.h"
#include "app/depth_range_tally.h"
#include "app/frame_log.h"
#include "app/frame_renders.h"
#include "app/memory_check.h"
#include "app/progress.h"
#include "app/reconstruct_options.h"
#include "app/reconstruct_report.h"
#include "app/run_control.h"
#include "core/atomic_output.h"
#include "core/error.h"
#include "core/mapped_file.h"
#include "core/version.h"
#include "slam/reconstruction.h"
#include "io/trajectory_io.h"
#include <nlohmann/json.hpp>
#include "vdb/scene.h"
#include "vdb/scene_frame.h"

namespace vf::app {
namespace {

void checkGpuFits(const ReconstructOptions& o, const ReconstructionOptions& r, const Intrinsics& camera) {
  GpuMemory gpu;
  if (r.device == Device::Cuda && cudaMemoryInfo(gpu.free_bytes, gpu.total_bytes))
    checkFitsGpu(Pipeline::startupDeviceBytes(camera, r.with_classes), gpu,
                 "fusing " + o.dataset + " (" + std::to_string(camera.width) + "x" + std::to_string(camera.height) + ")");
}

// A run that fused nothing wrote nothing worth keeping: say why, from the most common reason.
std::string nothingFusedMessage(const ReconstructOptions& o, const Reconstruction& run) {
  std::map<LostReason, int> count;
  const LostFrame* example = nullptr;
  for (const LostFrame& l : run.lostFrames()) {
    const int n = ++count[l.reason];
    if (!example || n > count[example->reason]) example = &l;
  }
  std::string message = o.dataset + ": no frame was fused (" + std::to_string(run.framesDone()) + " frames";
  if (example)
    message += "; " + std::to_string(count[example->reason]) + " with " + lostReasonName(example->reason) + ", e.g. " +
               example->name + ": " + example->why;
  message += ")";
  if (example && example->reason == LostReason::NoDepth)
    message += ". Check --depth-scale (the depth's units per metre) and --max-depth-m (the fusion range)";
  if (example && example->reason == LostReason::OutOfReach)
    message += ". The recorded poses are far from their origin; --poses icp tracks from the first frame instead";
  return message + "; no scene was written";
}

// How to open the source again for a texture bake (app/bake_frames.h), with absolute paths so
// that the bake may run from another folder.
std::string bakeSourceJson(const ReconstructOptions& o, const ReconstructionOptions& fusion) {
  namespace fs = std::filesystem;
  nlohmann::json j;
  j["path"] = fs::absolute(o.dataset).lexically_normal().string();
  j["format"] = o.source.format;
  if (!o.intrinsics.empty()) j["intrinsics"] = o.intrinsics;
  else if (o.source.intrinsics) j["intrinsics"] = *o.source.intrinsics;
  if (o.source.depth_units_per_metre) j["depth_units_per_metre"] = *o.source.depth_units_per_metre;
  j["min_confidence"] = o.source.min_confidence;
  if (!o.labels_dir.empty()) {
    j["labels"] = fs::absolute(o.labels_dir).lexically_normal().string();
    j["labels_missing"] = o.labels_missing;
    if (!o.classes_file.empty()) j["classes_file"] = fs::absolute(o.classes_file).lexically_normal().string();
  }
  j["dynamic_classes"] = fusion.dynamic_class_ids;
  return j.dump();
}

void runReconstruct(const ReconstructOptions& o) {
  claimOutputs(o);
  SourceOptions source_options = o.source;
  if (!o.intrinsics.empty()) source_options.intrinsics = o.intrinsics;
  std::unique_ptr<FrameSource> source = openFrameSource(o.dataset, source_options);
  std::string photometric_note;
  const bool photometric = photometricTermWanted(source_options, *source, &photometric_note);
  if (!photometric_note.empty() && !o.quiet) std::fprintf(stderr, "%s\n", photometric_note.c_str());
  if (o.labels_dir.empty() && (!o.classes_file.empty() || !o.dynamic_classes.empty()))
    throw Error("--classes and --dynamic-classes need --labels DIR (per-frame label maps)");
  LabeledFrameSource* labeled = nullptr;
  if (!o.labels_dir.empty()) {
    auto wrapped = std::make_unique<LabeledFrameSource>(std::move(source), o.labels_dir, loadClassTable(o),
                                                        parseMissingLabels(o.labels_missing));
    labeled = wrapped.get();
    source = std::move(wrapped);
  }
  ReconstructionOptions fusion = fusionOptions(o, labeled, photometric);
  // ICP weighs depth readings by the noise of the sensor that took them (core/frame.h).
  if (const std::optional<float> noise = source->depthNoiseQuadratic()) fusion.params.icp.depth_noise_quadratic = *noise;
  fusion.settings = runSettings(o, *source, fusion.device);
  checkGpuFits(o, fusion, source->depthIntrinsics());
  Reconstruction run(*source, fusion);
  if (!o.quiet)
    std::fprintf(stderr, "%s: %d frames, %dx%d, voxels of %.2f mm, depth up to %.1f m, device %s\n",
                 source->description().c_str(), run.frameCount(), source->depthIntrinsics().width,
                 source->depthIntrinsics().height, fusion.params.volume.voxel_size_m * 1000.f, o.max_depth_m,
                 deviceName(run.pipeline().device()).c_str());
  if (o.resume) {
    run.resume(o.checkpoint());
    if (!o.quiet)
      std::fprintf(stderr, "resuming after frame %d of %d from %s\n", run.framesDone(), run.frameCount(),
                   o.checkpoint().c_str());
  } else if (!o.output.empty()) {
    std::filesystem::remove(o.checkpoint());  // --force: a stale checkpoint must not be resumed later
  }

  SceneMetadata meta;
  meta.source = o.dataset;
  meta.software_version = VDBFUSE_VERSION_STRING;
  if (labeled) meta.classes = labeled->classes();
  meta.source_options_json = bakeSourceJson(o, fusion);
  FrameLog frame_log;  // --frame-log: the first pass's frames (a resumed run's from before, too)
  if (o.resume && !o.frame_log.empty() && std::filesystem::exists(o.frame_log))
    frame_log.resume(readRegularFile(o.frame_log, "frame log", kMaxTextFileBytes),
                     run.pass() == 2 ? run.frameCount() : run.framesDone(), run.trajectory());
  // Trajectory and scene of the frames done (and the checkpoint), each written atomically. The
  // scene records gravity's up and the camera for its exports (vdb/scene_frame.h).
  struct Written {
    size_t voxels = 0;
    SceneUp up;
  };
  // The scene first: it is the large one, so a full disk fails it before anything is replaced.
  auto writeOutputs = [&](bool with_checkpoint) {
    Written w;
    if (!o.output.empty()) {
      meta.frame_count = run.framesFused();
      meta.trajectory_tum = formatTumTrajectory(run.trajectory());  // what a texture bake needs
      // Straight from the bricks: the scene's grids in memory would take twice the bricks' memory.
      const BrickVolumeView bricks = run.pipeline().hostVolume();  // one download on CUDA
      w.up = setSceneFrame(meta, bricks, run.trajectory(), *source);
      w.voxels = writeSceneFromBricks(bricks, meta, o.output);
    }
    if (!o.trajectory.empty()) writeTumTrajectory(o.trajectory, run.trajectory());
    if (!o.odometry.empty()) writeTumTrajectory(o.odometry, run.pass() == 2 ? run.odometry() : run.trajectory());
    if (!o.frame_log.empty()) writeFileAtomic(o.frame_log, frame_log.csv());
    if (o.output.empty()) return w;
    if (with_checkpoint) run.saveCheckpoint(o.checkpoint());
    return w;
  };

  RenderOutputs renders(o.renders_dir, o.video);
  StopSignals stop("finishing this frame, then saving the scene and a checkpoint; a second signal waits for the save");
  auto progress = std::make_unique<ProgressBar>(run.frameCount(), !o.quiet);
  Reconstruction::Callbacks callbacks;
  std::vector<int> bricks_per_frame;
  DepthRangeTally depth_range(fusion.params.measurement.min_depth_m, fusion.params.measurement.max_depth_m);
  callbacks.on_frame = [&](const RgbdFrame& frame, const FrameResult& result) {
    if (result.integrated) bricks_per_frame.push_back(result.bricks_fused);
    if (run.pass() == 1) {
      if (!o.frame_log.empty()) frame_log.add(frame, result);
      renders.add(run.framesDone() - 1, frame, run.pipeline());
      if (result.integrated) depth_range.add(frame.depth);
    }
    const size_t lost = run.lostFrames().size();
    progress->update(run.framesDone(), lost == 0 || run.pass() == 2 ? "" : std::to_string(lost) + " lost");
  };
  // Pass 1's figures, kept when the second pass starts (its pipeline has a timer of its own).
  std::optional<StageTimer> first_pass_timer;
  double first_pass_s = 0;
  int first_pass_frames = 0;
  auto start = std::chrono::steady_clock::now();
  callbacks.on_second_pass = [&](const slam::GlobalReport& report) {
    progress->finish();
    first_pass_timer = run.firstPassTimer();
    first_pass_s = std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
    first_pass_frames = run.frameCount();
    if (!o.quiet) {
      const std::string maps = report.maps > 1 ? ", " + std::to_string(report.maps_joined) + " of " +
                                                     std::to_string(report.maps - 1) + " new maps joined to the older"
                                               : "";
      if (report.moved())
        std::fprintf(stderr, "loop closure: %d of %d loops hold%s; fusing again at the optimised poses (frames moved up to %.1f cm)\n",
                     report.loops_accepted, report.loops_found, maps.c_str(), 100.0 * report.largest_correction_m);
      else  // several maps, none moved: fused together as they were placed
        std::fprintf(stderr, "loop closure: %d of %d loops hold%s; fusing every map again into one scene\n",
                     report.loops_accepted, report.loops_found, maps.c_str());
    }
    bricks_per_frame.clear();
    progress = std::make_unique<ProgressBar>(run.frameCount(), !o.quiet);
  };
  callbacks.should_stop = [&] { return stop.received() != 0; };
  callbacks.checkpoint_every = o.checkpoint_every;
  callbacks.on_checkpoint = [&] { writeOutputs(true); };
  const int first = run.framesDone();
  const bool resumed_in_second_pass = run.pass() == 2;
  start = std::chrono::steady_clock::now();
  const Reconstruction::Outcome outcome = run.run(callbacks, o.bench);
  progress->finish();
  const double wall_s = std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
  renders.close();

  if (outcome != Reconstruction::Outcome::Finished) {
    const bool full = outcome == Reconstruction::Outcome::VolumeFull;
    if (full)
      std::fprintf(stderr, "\nthe volume is full after frame %d of %d: %d bricks (%.1f GiB) are all the memory allows\n",
                   run.framesDone(), run.frameCount(), run.pipeline().brickCount(),
                   double(run.pipeline().volumeBytes()) / double(1u << 30));
    else
      std::fprintf(stderr, "\n%s: stopping after frame %d of %d\n", StopSignals::name(stop.received()).c_str(),
                   run.framesDone(), run.frameCount());
    writeOutputs(true);
    if (!o.output.empty())
      std::fprintf(stderr, "wrote %s%s and %s (%d frames); %s\n", o.output.c_str(),
                   o.trajectory.empty() ? "" : (", " + o.trajectory).c_str(), o.checkpoint().c_str(), run.framesDone(),
                   full ? "raise --voxel-size-m or lower --max-depth-m to fit the scene"
                        : "continue with the same command and --resume");
    if (full) throw Error("the volume ran out of memory after frame " + std::to_string(run.framesDone()));
    throw ExitWithStatus(StopSignals::exitStatus(stop.received()), "interrupted");
  }

  printTrackingSummary(run.frameCount(), run.lostFrames(), run.framesFused(), run.tracker().relocalisations());
  printPriorHeld(run.tracker().priorHeldStretches());
  if (run.framesFused() == 0) throw Error(nothingFusedMessage(o, run));
  if (labeled) printLabelSummary(labeled->stats(), labeled->classes(), run.frameCount());
  // A resumed run counted only the frames after the checkpoint: still a fair share.
  if (const std::string dropped = depth_range.report(); !dropped.empty()) std::printf("%s\n", dropped.c_str());
  if (fusion.poses != PoseSource::Given) printLoopClosure(run.globalReport(), fusion.global.loop_closure);
  // The stage table is for whoever tunes the engine; a user reads the frames and the time.
  const bool stage_table = o.verbose || o.bench;
  if (first_pass_timer) {
    std::printf("\nfirst pass (tracking and fusion):");
    printTimingTable(*first_pass_timer, first_pass_frames - first, first_pass_s, {}, stage_table);
    std::printf(run.globalReport().moved() ? "\nsecond pass (fusion at the optimised poses):"
                                           : "\nsecond pass (fusion at the same poses):");
    printTimingTable(run.pipeline().timer(), run.frameCount(), wall_s - first_pass_s, std::move(bricks_per_frame),
                     stage_table);
  } else {
    if (resumed_in_second_pass) std::printf("\nsecond pass, resumed:");
    printTimingTable(run.pipeline().timer(), run.frameCount() - first, wall_s, std::move(bricks_per_frame), stage_table);
  }
  const auto t0 = std::chrono::steady_clock::now();
  const Written written = writeOutputs(false);
  if (!o.output.empty()) {
    std::filesystem::remove(o.checkpoint());  // the run is complete: nothing to resume
    std::printf("up: %s (%s)\n", written.up.source.c_str(), written.up.detail.c_str());
    std::printf("wrote %s (%zu active voxels) in %.2f s\n", o.output.c_str(), written.voxels,
                std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count());
  }
  printMemory(run.pipeline().brickCount(), run.pipeline().volumeBytes());
  if (!o.report_json.empty()) {
    RunFigures figures;
    figures.frames = run.frameCount();
    figures.fused = run.framesFused();
    figures.relocalisations = run.tracker().relocalisations();
    figures.maps = run.tracker().maps();
    figures.prior_held_frames = priorHeldFrames(run.tracker().priorHeldStretches());
    figures.passes = run.pass();
    figures.bricks_restarted = run.globalReport().bricks_restarted;
    figures.resumed_after_frame = first;
    figures.lost = run.lostFrames();
    figures.seconds = wall_s;
    figures.bricks = run.pipeline().brickCount();
    figures.active_voxels = written.voxels;
    figures.device = deviceName(run.pipeline().device());
    writeFileAtomic(o.report_json, runFiguresJson(figures));
  }
}

void setupReconstructCommand(CLI::App& root) {
  auto o = std::make_shared<ReconstructOptions>();
  CLI::App* cmd = root.add_subcommand("reconstruct", "Fuse an RGB-D sequence into a scene (.vdb)");
  addReconstructOptions(*cmd, *o);
  cmd->callback([o] {
    // DESIGN.md: the trajectory travels beside the scene (scene.vdb -> scene.txt), where the
    // viewer and the editor look for it.
    ReconstructOptions options = *o;
    if (options.trajectory.empty() && !options.output.empty())
      options.trajectory = std::filesystem::path(options.output).replace_extension(".txt").string();
    runReconstruct(options);
  });
}

}  // namespace

VF_REGISTER_COMMAND(10, setupReconstructCommand);

}  // namespace vf::app
