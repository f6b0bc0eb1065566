#include "app/reconstruct_options.h"

#include <filesystem>

#include "app/output_policy.h"
#include "app/usage_errors.h"
#include "core/error.h"
#include "io/class_table_io.h"

namespace vf::app {
namespace {

PoseSource parsePoses(const std::string& s) {
  if (s == "icp") return PoseSource::Icp;
  if (s == "given") return PoseSource::Given;
  if (s == "given+icp") return PoseSource::GivenIcp;
  throw Error("--poses " + s + ": expected icp, given or given+icp");
}

}  // namespace

void addReconstructOptions(CLI::App& cmd, ReconstructOptions& o) {
  cmd.add_option("dataset", o.dataset, std::string("RGB-D input, detected from its files:\n") + kKnownLayouts)->required();
  cmd.add_option("-o,--output", o.output, "Scene file to write (.vdb)");
  cmd.add_option("--trajectory", o.trajectory, "Camera trajectory to write (TUM format; default: the scene's path with .txt)");
  cmd.add_option("--voxel-size-m", o.voxel_size_m, "Voxel edge in metres")->capture_default_str();
  cmd.add_option("--truncation-m", o.truncation_m, "TSDF truncation in metres (default: 5 voxels)");
  cmd.add_option("--max-depth-m", o.max_depth_m, "Depth readings further away are not fused")->capture_default_str();
  cmd.add_option("--fuse-depth", o.fuse_depth,
                 "filtered (the bilateral-filtered depth tracking uses: less noise, fewer bricks) or raw (as "
                 "KinectFusion: the finest detail, and the sensor's noise)")
      ->capture_default_str();
  cmd.add_option("--volume-size", o.volume_size)->group("");  // removed: says so
  cmd.add_option("--max-frames", o.max_frames, "Fuse at most this many frames")->check(atLeast(1));
  cmd.add_option("--device", o.device, "cpu, cuda or auto (CUDA when a GPU is usable)")->capture_default_str();
  cmd.add_option("--poses", o.poses, "icp, given (recorded poses, in their own world frame) or given+icp")
      ->capture_default_str();
  cmd.add_option("--intrinsics", o.intrinsics, "fx,fy,cx,cy overriding the dataset's calibration");
  cmd.add_option("--format", o.source.format, "auto, tum, r3d, r3d-export, 7scenes, replica, scannet or redwood")
      ->capture_default_str();
  addDatasetOptions(cmd, o.source);
  cmd.add_option("--min-confidence", o.source.min_confidence, "Record3D: lowest depth confidence kept (0-2)")
      ->capture_default_str();
  cmd.add_option("--labels", o.labels_dir, "Folder of per-frame label maps (8/16-bit PNG class ids, by file stem or frame index)");
  cmd.add_option("--classes", o.classes_file, "Class table JSON for --labels (default: DIR/classes.json); label ids it "
                 "does not name are fused as unknown and reported");
  cmd.add_option("--dynamic-classes", o.dynamic_classes, "Classes kept out of tracking and geometry (names or ids, e.g. person)");
  cmd.add_option("--mask-dilation-px", o.mask_dilation_px, "Grow dynamic-class masks by this many pixels (default 4)");
  cmd.add_option("--labels-missing", o.labels_missing, "A frame without a label map: skip (fuse it without labels) or error")
      ->capture_default_str();
  cmd.add_option("--class-vote", o.class_vote, "majority or probabilistic class fusion")->capture_default_str();
  cmd.add_option("--class-vote-seed", o.class_vote_seed, "Seed of --class-vote probabilistic")->capture_default_str();
  cmd.add_option("--renders", o.renders_dir, "Write input | predicted color | shaded model PNGs per frame here");
  cmd.add_option("--video", o.video, "Write the same panels as an MP4 video");
  cmd.add_flag("--bench", o.bench, "Decode all frames first, then time the fusion stages alone");
  cmd.add_flag("-v,--verbose", o.verbose, "Also print the time each fusion stage took (--bench does too)");
  cmd.add_flag("-q,--quiet", o.quiet, "No progress bar");
  cmd.add_flag("-f,--force", o.force, "Overwrite existing outputs");
  cmd.add_option("--checkpoint-every", o.checkpoint_every,
                 "Every N frames write the scene, the trajectory and OUTPUT.checkpoint (to --resume from); "
                 "SIGINT/SIGTERM always finish the frame and write them");
  cmd.add_option("--loop-closure", o.loop_closure,
                 "on: find where the camera came back, optimise the poses and fuse again at them; off: one pass")
      ->capture_default_str()
      ->check(CLI::IsMember({"on", "off"}));
  cmd.add_option("--odometry", o.odometry,
                 "Also write the trajectory tracking gave before the loop closure moved it (TUM format)");
  cmd.add_option("--report-json", o.report_json,
                 "Write the run's figures as JSON once it finished: frames, tracked, fused, lost (by reason), "
                 "passes, bricks_restarted, seconds, peak_mib, bricks, active_voxels, device");
  cmd.add_option("--frame-log", o.frame_log,
                 "Write a CSV row per frame of the first pass: how well it matched the model, the directions "
                 "its view left free, how far it moved, and why a lost frame was lost (README \"Reading a run's "
                 "frame log\")");
  cmd.add_flag("--resume", o.resume, "Continue an interrupted run from OUTPUT.checkpoint (same dataset and options)");
}

ClassTable loadClassTable(const ReconstructOptions& o) {
  if (!o.classes_file.empty()) return readClassTable(o.classes_file);
  const std::string path = (std::filesystem::path(o.labels_dir) / "classes.json").string();
  if (!std::filesystem::exists(path))
    throw Error("--labels " + o.labels_dir + " has no classes.json; name the class table with --classes FILE.json " +
                "(e.g. samples/classes/ade20k.json)");
  return readClassTable(path);
}

RunSettings runSettings(const ReconstructOptions& o, const FrameSource& source, Device device) {
  std::error_code ec;
  const std::filesystem::path dataset = std::filesystem::weakly_canonical(o.dataset, ec);
  return {{"dataset", ec ? o.dataset : dataset.string()}, {"dataset_frames", std::to_string(source.size())},
          {"max_frames", std::to_string(o.max_frames)},     {"device", deviceName(device)},
          {"poses", o.poses},                               {"format", o.source.format},
          {"dataset_options", datasetOptionsKey(o.source)},
          {"min_confidence", std::to_string(o.source.min_confidence)},
          {"max_depth_m", std::to_string(o.max_depth_m)},   {"intrinsics", o.intrinsics},
          {"fuse_depth", o.fuse_depth},
          {"labels", o.labels_dir},                         {"classes", o.classes_file},
          {"dynamic_classes", o.dynamic_classes},
          {"mask_dilation_px", o.mask_dilation_px ? std::to_string(*o.mask_dilation_px) : ""},
          {"labels_missing", o.labels_missing},
          {"class_vote", o.class_vote + ":" + std::to_string(o.class_vote_seed)},
          {"loop_closure", o.loop_closure}};
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
  if (!o.video.empty()) OutputPolicy::requireExtension(o.video, {".mp4"}, "--video");
  if (!o.report_json.empty()) OutputPolicy::requireExtension(o.report_json, {".json"}, "--report-json");
  if (!o.frame_log.empty()) OutputPolicy::requireExtension(o.frame_log, {".csv"}, "--frame-log");
  OutputPolicy outputs(o.force || o.resume);
  outputs.input(o.dataset);
  if (!o.labels_dir.empty()) outputs.input(o.labels_dir);
  if (!o.output.empty()) outputs.file(o.output, "-o");
  if (!o.trajectory.empty()) outputs.file(o.trajectory, "--trajectory");
  if (!o.odometry.empty()) outputs.file(o.odometry, "--odometry");
  if (!o.report_json.empty()) outputs.file(o.report_json, "--report-json");
  if (!o.frame_log.empty()) outputs.file(o.frame_log, "--frame-log");
  if (!o.video.empty()) outputs.file(o.video, "--video");
  if (!o.output.empty()) outputs.file(o.checkpoint(), "the checkpoint");
  if (!o.renders_dir.empty()) outputs.filesInto(o.renders_dir, "--renders");
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
  if (o.fuse_depth != "filtered" && o.fuse_depth != "raw")
    throw Error("--fuse-depth " + o.fuse_depth + ": expected filtered or raw");
  r.params.integration.integrate_filtered_depth = o.fuse_depth == "filtered";
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
  r.global.loop_closure = o.loop_closure == "on";
  r.with_classes = labeled != nullptr;
  if (labeled && !o.dynamic_classes.empty())
    r.dynamic_class_ids = labeled->classes().resolve({o.dynamic_classes}, "--dynamic-classes");
  return r;
}

}  // namespace vf::app
