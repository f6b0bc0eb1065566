// vdbfuse reconstruct DATASET -o scene.vdb: parses the options, runs a Reconstruction
// (fusion/reconstruction.h) and writes the scene, the trajectory and, when asked or interrupted,
// a checkpoint to resume from.
#include <chrono>
#include <cstdio>
#include <filesystem>
#include <optional>

#include "app/command_registry.h"
#include "app/frame_renders.h"
#include "app/memory_check.h"
#include "app/open_source.h"
#include "app/output_policy.h"
#include "app/progress.h"
#include "app/reconstruct_report.h"
#include "app/run_control.h"
#include "core/error.h"
#include "core/version.h"
#include "fusion/reconstruction.h"
#include "io/class_table_io.h"
#include "io/labeled_source.h"
#include "io/trajectory_io.h"
#include "vdb/scene.h"

namespace vf::app {
namespace {

struct ReconstructOptions {
  std::string dataset, output, trajectory;
  std::optional<std::string> volume_size;  // gone: kept only to say so
  float voxel_size_m = VolumeSpec{}.voxel_size_m;
  float truncation_m = 0;  // 0 = 5 voxels
  float max_depth_m = MeasurementParams{}.max_depth_m;
  int max_frames = 0;
  std::string device = "auto", poses = "icp", intrinsics;
  SourceOptions source;
  std::string renders_dir, video;
  bool bench = false, quiet = false, force = false, resume = false;
  int checkpoint_every = 0;  // frames; 0 = checkpoints only when interrupted
  // Semantic fusion.
  std::string labels_dir, classes_file, dynamic_classes;  // classes: default labels_dir/classes.json
  std::optional<int> mask_dilation_px;
  std::string labels_missing = "skip", class_vote = "majority";
  uint32_t class_vote_seed = 0;

  std::string checkpoint() const { return output + ".checkpoint"; }
};

PoseSource parsePoses(const std::string& s) {
  if (s == "icp") return PoseSource::Icp;
  if (s == "given") return PoseSource::Given;
  if (s == "given+icp") return PoseSource::GivenIcp;
  throw Error("--poses " + s + ": expected icp, given or given+icp");
}

// The class table that goes with --labels: --classes, else DIR/classes.json.
ClassTable loadClassTable(const ReconstructOptions& o) {
  if (!o.classes_file.empty()) return readClassTable(o.classes_file);
  const std::string path = (std::filesystem::path(o.labels_dir) / "classes.json").string();
  if (!std::filesystem::exists(path))
    throw Error("--labels " + o.labels_dir + " has no classes.json; name the class table with --classes FILE.json " +
                "(e.g. samples/classes/ade20k.json)");
  return readClassTable(path);
}

// What must not change between a run and its resumption; the checkpoint checks the camera and
// the volume itself.
RunSettings runSettings(const ReconstructOptions& o, const FrameSource& source, Device device) {
  std::error_code ec;
  const std::filesystem::path dataset = std::filesystem::weakly_canonical(o.dataset, ec);
  return {{"dataset", ec ? o.dataset : dataset.string()}, {"dataset_frames", std::to_string(source.size())},
          {"max_frames", std::to_string(o.max_frames)},     {"device", deviceName(device)},
          {"poses", o.poses},                               {"format", o.source.format},
          {"dataset_options", datasetOptionsKey(o.source)},
          {"min_confidence", std::to_string(o.source.min_confidence)},
          {"max_depth_m", std::to_string(o.max_depth_m)},   {"intrinsics", o.intrinsics},
          {"labels", o.labels_dir},                         {"classes", o.classes_file},
          {"dynamic_classes", o.dynamic_classes},
          {"mask_dilation_px", o.mask_dilation_px ? std::to_string(*o.mask_dilation_px) : ""},
          {"labels_missing", o.labels_missing},
          {"class_vote", o.class_vote + ":" + std::to_string(o.class_vote_seed)}};
}

void claimOutputs(const ReconstructOptions& o) {
  if (o.output.empty() && !o.bench) throw Error("reconstruct: give an output scene with -o scene.vdb");
  if ((o.checkpoint_every > 0 || o.resume) && o.output.empty())
    throw Error("--checkpoint-every and --resume need -o scene.vdb (the checkpoint is written beside it)");
  if (o.checkpoint_every < 0) throw Error("--checkpoint-every " + std::to_string(o.checkpoint_every) + ": expected frames > 0");
  if (o.resume) {
    if (o.force) throw Error("--resume continues an interrupted run and --force starts a new one; choose one");
    if (!o.video.empty()) throw Error("--video cannot be continued by --resume; leave it out (--renders can)");
    if (!std::filesystem::exists(o.checkpoint()))
      throw Error("--resume: " + o.checkpoint() + " does not exist (the run finished, or was started without -o " +
                  o.output + ")");
  } else if (!o.output.empty() && std::filesystem::exists(o.checkpoint()) && !o.force) {
    throw Error(o.checkpoint() + " holds an interrupted run; pass --resume to continue it or --force to start over");
  }
  // A resumed run replaces the interrupted run's outputs: they are its own.
  if (!o.output.empty()) OutputPolicy::requireExtension(o.output, {".vdb"}, "-o");
  OutputPolicy outputs(o.force || o.resume);
  outputs.input(o.dataset);
  if (!o.labels_dir.empty()) outputs.input(o.labels_dir);
  if (!o.output.empty()) outputs.file(o.output, "-o");
  if (!o.trajectory.empty()) outputs.file(o.trajectory, "--trajectory");
  if (!o.video.empty()) outputs.file(o.video, "--video");
  if (!o.output.empty()) outputs.file(o.checkpoint(), "the checkpoint");
  if (!o.renders_dir.empty() && std::filesystem::exists(o.renders_dir) && !o.force && !o.resume)
    for (const auto& entry : std::filesystem::directory_iterator(o.renders_dir))
      if (entry.path().filename().string().rfind("frame_", 0) == 0)
        throw Error("--renders " + o.renders_dir + " already holds frame_*.png renders; pass --force to overwrite them");
}

ReconstructionOptions fusionOptions(const ReconstructOptions& o, const LabeledFrameSource* labeled, bool photometric) {
  if (o.volume_size)
    throw Error("--volume-size is gone: the volume has no box any more and grows with the scene; set the detail with "
                "--voxel-size-m and the range with --max-depth-m");
  ReconstructionOptions r;
  r.params.volume.voxel_size_m = o.voxel_size_m;
  r.params.volume.truncation_m = o.truncation_m;
  r.params.measurement.max_depth_m = o.max_depth_m;
  if (o.mask_dilation_px) r.params.dynamic_mask_dilation_px = *o.mask_dilation_px;
  if (o.class_vote != "majority" && o.class_vote != "probabilistic")
    throw Error("--class-vote " + o.class_vote + ": expected majority or probabilistic");
  r.params.integration.class_vote = o.class_vote == "majority" ? ClassVote::Majority : ClassVote::Probabilistic;
  r.params.integration.class_vote_seed = o.class_vote_seed;
  if (!photometric) r.params.icp.photometric_weight = 0;
  r.params.validate();
  r.device = resolveDevice(parseDevice(o.device));
  r.poses = parsePoses(o.poses);
  r.max_frames = o.max_frames;
  r.with_classes = labeled != nullptr;
  if (labeled && !o.dynamic_classes.empty())
    r.dynamic_class_ids = resolveClassList(labeled->classes(), o.dynamic_classes, "--dynamic-classes");
  return r;
}

void checkGpuFits(const ReconstructOptions& o, const ReconstructionOptions& r, const Intrinsics& camera) {
  GpuMemory gpu;
  if (r.device == Device::Cuda && cudaMemoryInfo(gpu.free_bytes, gpu.total_bytes))
    checkFitsGpu(Pipeline::startupDeviceBytes(camera, r.with_classes), gpu,
                 "fusing " + o.dataset + " (" + std::to_string(camera.width) + "x" + std::to_string(camera.height) + ")");
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
  fusion.settings = runSettings(o, *source, fusion.device);
  checkGpuFits(o, fusion, source->depthIntrinsics());
  Reconstruction run(*source, fusion);
  Pipeline& pipeline = run.pipeline();
  if (!o.quiet)
    std::fprintf(stderr, "%s: %d frames, %dx%d, voxels of %.2f mm, depth up to %.1f m, device %s\n",
                 source->description().c_str(), run.frameCount(), source->depthIntrinsics().width,
                 source->depthIntrinsics().height, fusion.params.volume.voxel_size_m * 1000.f, o.max_depth_m,
                 deviceName(pipeline.device()).c_str());
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
  // Trajectory and scene of the frames done (and the checkpoint), each written atomically.
  auto writeOutputs = [&](bool with_checkpoint) -> size_t {
    if (!o.trajectory.empty()) writeTumTrajectory(o.trajectory, run.trajectory());
    if (o.output.empty()) return 0;
    meta.frame_count = run.framesDone() - pipeline.framesLost();
    const Scene scene = sceneFromBricks(pipeline.hostVolume(), meta);
    writeScene(scene, o.output);
    if (with_checkpoint) run.saveCheckpoint(o.checkpoint());
    return scene.activeVoxelCount();
  };

  RenderOutputs renders(o.renders_dir, o.video);
  StopSignals stop("finishing this frame, then saving the scene and a checkpoint; a second signal waits for the save");
  ProgressBar progress(run.frameCount(), !o.quiet);
  Reconstruction::Callbacks callbacks;
  callbacks.on_frame = [&](const RgbdFrame& frame, const FrameResult&) {
    renders.add(run.framesDone() - 1, frame, pipeline);
    const size_t lost = run.lostFrames().size();
    progress.update(run.framesDone(), lost == 0 ? "" : std::to_string(lost) + " lost");
  };
  callbacks.should_stop = [&] { return stop.received() != 0; };
  callbacks.checkpoint_every = o.checkpoint_every;
  callbacks.on_checkpoint = [&] { writeOutputs(true); };
  const int first = run.framesDone();
  const auto start = std::chrono::steady_clock::now();
  const Reconstruction::Outcome outcome = run.run(callbacks, o.bench);
  progress.finish();
  const double wall_s = std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
  renders.close();

  if (outcome != Reconstruction::Outcome::Finished) {
    const bool full = outcome == Reconstruction::Outcome::VolumeFull;
    if (full)
      std::fprintf(stderr, "\nthe volume is full after frame %d of %d: %d bricks (%.1f GiB) are all the memory allows\n",
                   run.framesDone(), run.frameCount(), pipeline.brickCount(),
                   double(pipeline.volumeBytes()) / double(1u << 30));
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

  printTrackingSummary(run.frameCount(), run.lostFrames());
  if (labeled) printLabelSummary(labeled->stats(), labeled->classes(), run.frameCount());
  printTimingTable(pipeline.timer(), run.frameCount() - first, wall_s);
  const auto t0 = std::chrono::steady_clock::now();
  const size_t voxels = writeOutputs(false);
  if (!o.output.empty()) {
    std::filesystem::remove(o.checkpoint());  // the run is complete: nothing to resume
    std::printf("wrote %s (%zu active voxels) in %.2f s\n", o.output.c_str(), voxels,
                std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count());
  }
  printMemory(pipeline.brickCount(), pipeline.volumeBytes());
}

void setup(CLI::App& root) {
  auto o = std::make_shared<ReconstructOptions>();
  CLI::App* cmd = root.add_subcommand("reconstruct", "Fuse an RGB-D sequence into a scene (.vdb)");
  cmd->add_option("dataset", o->dataset, std::string("RGB-D input, detected from its files:\n") + kKnownLayouts)->required();
  cmd->add_option("-o,--output", o->output, "Scene file to write (.vdb)");
  cmd->add_option("--trajectory", o->trajectory, "Camera trajectory to write (TUM format; default: the scene's path with .txt)");
  cmd->add_option("--voxel-size-m", o->voxel_size_m, "Voxel edge in metres")->capture_default_str();
  cmd->add_option("--truncation-m", o->truncation_m, "TSDF truncation in metres (default: 5 voxels)");
  cmd->add_option("--max-depth-m", o->max_depth_m, "Depth readings further away are not fused")->capture_default_str();
  cmd->add_option("--volume-size", o->volume_size)->group("");  // removed: says so
  cmd->add_option("--max-frames", o->max_frames, "Fuse at most this many frames");
  cmd->add_option("--device", o->device, "cpu, cuda or auto (CUDA when a GPU is usable)")->capture_default_str();
  cmd->add_option("--poses", o->poses, "icp, given (recorded poses, in their own world frame) or given+icp")
      ->capture_default_str();
  cmd->add_option("--intrinsics", o->intrinsics, "fx,fy,cx,cy overriding the dataset's calibration");
  cmd->add_option("--format", o->source.format, "auto, tum, r3d, r3d-export, 7scenes, replica, scannet or redwood")
      ->capture_default_str();
  addDatasetOptions(*cmd, o->source);
  cmd->add_option("--min-confidence", o->source.min_confidence, "Record3D: lowest depth confidence kept (0-2)")
      ->capture_default_str();
  cmd->add_option("--labels", o->labels_dir, "Folder of per-frame label maps (8/16-bit PNG class ids, by file stem or frame index)");
  cmd->add_option("--classes", o->classes_file, "Class table JSON for --labels (default: DIR/classes.json); label ids it "
                  "does not name are fused as unknown and reported");
  cmd->add_option("--dynamic-classes", o->dynamic_classes, "Classes kept out of tracking and geometry (names or ids, e.g. person)");
  cmd->add_option("--mask-dilation-px", o->mask_dilation_px, "Grow dynamic-class masks by this many pixels (default 4)");
  cmd->add_option("--labels-missing", o->labels_missing, "A frame without a label map: skip (fuse it without labels) or error")
      ->capture_default_str();
  cmd->add_option("--class-vote", o->class_vote, "majority or probabilistic class fusion")->capture_default_str();
  cmd->add_option("--class-vote-seed", o->class_vote_seed, "Seed of --class-vote probabilistic")->capture_default_str();
  cmd->add_option("--renders", o->renders_dir, "Write input | predicted color | shaded model PNGs per frame here");
  cmd->add_option("--video", o->video, "Write the same panels as an MP4 video");
  cmd->add_flag("--bench", o->bench, "Decode all frames first, then time the fusion stages alone");
  cmd->add_flag("-q,--quiet", o->quiet, "No progress bar");
  cmd->add_flag("-f,--force", o->force, "Overwrite existing outputs");
  cmd->add_option("--checkpoint-every", o->checkpoint_every,
                  "Every N frames write the scene, the trajectory and OUTPUT.checkpoint (to --resume from); "
                  "SIGINT/SIGTERM always finish the frame and write them");
  cmd->add_flag("--resume", o->resume, "Continue an interrupted run from OUTPUT.checkpoint (same dataset and options)");
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

VF_REGISTER_COMMAND(10, setup);

}  // namespace vf::app
