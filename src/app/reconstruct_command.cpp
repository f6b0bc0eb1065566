// vdbfuse reconstruct DATASET -o scene.vdb: the KinectFusion loop over a sequence, then the
// dense volume becomes the sparse scene document.
#include <sys/resource.h>

#include <chrono>
#include <cinttypes>
#include <cstdio>
#include <cstdlib>
#include <filesystem>
#include <map>
#include <optional>
#include <sstream>

#include "app/command_registry.h"
#include "app/frame_prefetcher.h"
#include "app/frame_renders.h"
#include "app/memory_check.h"
#include "app/open_source.h"
#include "app/progress.h"
#include "app/run_control.h"
#include "core/error.h"
#include "core/version.h"
#include "fusion/pipeline.h"
#include "fusion/pipeline_state.h"
#include "io/class_table_io.h"
#include "io/image_io.h"
#include "io/labeled_source.h"
#include "io/trajectory_io.h"
#include "io/video_writer.h"
#include "vdb/scene.h"
#include "vdb/scene_frame.h"

namespace vf::app {
namespace {

struct ReconstructOptions {
  std::string dataset;
  std::string output;
  std::string trajectory;
  std::string volume_size = "512";
  float voxel_size_m = 0;     // 0 = 3 m / largest dimension
  float truncation_m = 0;     // 0 = 5 voxels
  int max_frames = 0;
  std::string device = "auto";
  std::string renders_dir;
  std::string video;
  std::string poses = "icp";
  SourceOptions source;
  std::string intrinsics;
  bool bench = false;
  bool quiet = false;
  bool force = false;
  int checkpoint_every = 0;  // frames; 0 = checkpoints only when interrupted
  bool resume = false;
  // Semantic fusion.
  std::string labels_dir;
  std::string classes_file;       // default: labels_dir/classes.json
  std::string dynamic_classes;    // names or ids, comma-separated
  std::optional<int> mask_dilation_px;  // unset: PipelineParams default
  std::string labels_missing = "skip";
  std::string class_vote = "majority";
  uint32_t class_vote_seed = 0;
};

ClassVote parseClassVote(const std::string& s) {
  if (s == "majority") return ClassVote::Majority;
  if (s == "probabilistic") return ClassVote::Probabilistic;
  throw Error("--class-vote " + s + ": expected majority or probabilistic");
}

// The class table that goes with --labels: --classes, else DIR/classes.json.
ClassTable loadClassTable(const ReconstructOptions& o) {
  std::string path = o.classes_file;
  if (path.empty()) {
    path = (std::filesystem::path(o.labels_dir) / "classes.json").string();
    if (!std::filesystem::exists(path))
      throw Error("--labels " + o.labels_dir + " has no classes.json; name the class table with --classes FILE.json " +
                  "(e.g. samples/classes/ade20k.json)");
  }
  return readClassTable(path);
}

void printLabelSummary(const LabelStats& stats, const ClassTable& classes, int frames) {
  std::printf("labels: %d of %d frames labelled", stats.frames_labelled, frames);
  if (!stats.missing_files.empty()) {
    std::printf("; %zu without a label map (fused without labels):", stats.missing_files.size());
    const size_t shown = std::min<size_t>(stats.missing_files.size(), 5);
    for (size_t i = 0; i < shown; ++i) std::printf(" %s", stats.missing_files[i].c_str());
    if (shown < stats.missing_files.size()) std::printf(" ...");
  }
  std::printf("\n");
  if (!stats.unknown_id_pixels.empty()) {
    std::printf("labels: ids not in the class table (%zu classes named) were fused as unknown:",
                classes.classes.size());
    for (const auto& [id, pixels] : stats.unknown_id_pixels) std::printf(" %d (%lld px)", id, pixels);
    std::printf("\n");
  }
}

Vec3i parseVolumeSize(const std::string& text) {
  std::vector<int> v;
  std::stringstream ss(text);
  std::string item;
  while (std::getline(ss, item, ',')) {
    try {
      size_t used = 0;
      v.push_back(std::stoi(item, &used));
      if (used != item.size()) throw std::invalid_argument(item);
    } catch (const std::exception&) {
      throw Error("--volume-size " + text + ": expected N or X,Y,Z voxel counts");
    }
  }
  if (v.size() == 1) return {v[0], v[0], v[0]};
  if (v.size() == 3) return {v[0], v[1], v[2]};
  throw Error("--volume-size " + text + ": expected N or X,Y,Z voxel counts");
}

PoseSource parsePoses(const std::string& s) {
  if (s == "icp") return PoseSource::Icp;
  if (s == "given") return PoseSource::Given;
  if (s == "given+icp") return PoseSource::GivenIcp;
  throw Error("--poses " + s + ": expected icp, given or given+icp");
}

double peakResidentMiB() {
  rusage usage{};
  getrusage(RUSAGE_SELF, &usage);
  return double(usage.ru_maxrss) / 1024.0;  // ru_maxrss is in KiB on Linux
}

void printTimingTable(const StageTimer& timer, int frames, double wall_s) {
  std::printf("\n%-12s %10s %10s %10s\n", "stage", "median ms", "mean ms", "total s");
  double sum_median = 0;
  for (const std::string& stage : timer.stages()) {
    std::printf("%-12s %10.2f %10.2f %10.2f\n", stage.c_str(), timer.median(stage), timer.mean(stage),
                timer.total(stage) / 1000.0);
    if (stage == "measure" || stage == "track" || stage == "integrate" || stage == "raycast")
      sum_median += timer.median(stage);
  }
  std::printf("%-12s %10.2f   -> %.1f frames/s from the four stages' medians\n", "fusion", sum_median,
              sum_median > 0 ? 1000.0 / sum_median : 0.0);
  std::printf("%d frames in %.2f s (%.1f frames/s including I/O), peak memory %.0f MiB\n", frames, wall_s,
              wall_s > 0 ? frames / wall_s : 0.0, peakResidentMiB());
}

void refuseOverwrite(const std::string& path, bool force) {
  if (!path.empty() && std::filesystem::exists(path) && !force)
    throw Error(path + " already exists; pass --force to overwrite it");
}

// A long run must not fail at the very end because an output folder is missing.
void requireParentFolder(const std::string& path, const char* option) {
  if (path.empty()) return;
  const std::filesystem::path dir = std::filesystem::path(path).parent_path();
  if (!dir.empty() && !std::filesystem::is_directory(dir))
    throw Error(std::string(option) + " " + path + ": folder " + dir.string() + " does not exist");
}

bool hasRenders(const std::string& dir) {
  if (dir.empty() || !std::filesystem::is_directory(dir)) return false;
  for (const auto& entry : std::filesystem::directory_iterator(dir)) {
    const std::string name = entry.path().filename().string();
    if (name.rfind("frame_", 0) == 0 && entry.path().extension() == ".png") return true;
  }
  return false;
}

std::string checkpointPath(const ReconstructOptions& o) { return o.output + ".checkpoint"; }

// --- checkpoint annotations: the app's part of <output>.checkpoint (fusion/pipeline_state.h
// stores the pipeline's). Text lines; numbers that must survive bit for bit are hex floats.
constexpr const char* kCheckpointHeader = "vdbfuse-reconstruct-checkpoint 1";

using Settings = std::vector<std::pair<std::string, std::string>>;

std::string hexDouble(double v) {
  char text[40];
  std::snprintf(text, sizeof text, "%a", v);
  return text;
}

double parseHexDouble(const std::string& s, const std::string& path) {
  char* end = nullptr;
  const double v = std::strtod(s.c_str(), &end);
  if (end == s.c_str() || *end != '\0') throw Error("checkpoint " + path + ": malformed number '" + s + "'");
  return v;
}

std::string makeAnnotations(const Settings& settings, int frames_done, const std::vector<std::string>& lost,
                            const Trajectory& trajectory) {
  std::string out = std::string(kCheckpointHeader) + "\n";
  for (const auto& [key, value] : settings) out += "setting " + key + " " + value + "\n";
  out += "frames_done " + std::to_string(frames_done) + "\n";
  for (const std::string& l : lost) out += "lost " + l + "\n";
  for (const StampedPose& p : trajectory) {
    out += "pose " + hexDouble(p.timestamp);
    for (int i = 0; i < 16; ++i) out += " " + hexDouble(p.T_world_cam.matrix().data()[i]);
    out += "\n";
  }
  return out;
}

struct ResumeState {
  int frames_done = 0;
  std::vector<std::string> lost;
  Trajectory trajectory;
};

// Parses the annotations and checks that this run asks for what the checkpoint was made with.
ResumeState parseAnnotations(const std::string& text, const Settings& settings, const std::string& path) {
  std::istringstream in(text);
  std::string line;
  if (!std::getline(in, line) || line != kCheckpointHeader)
    throw Error("checkpoint " + path + " was not written by vdbfuse reconstruct");
  std::map<std::string, std::string> saved;
  ResumeState state;
  state.frames_done = -1;
  while (std::getline(in, line)) {
    const size_t space = line.find(' ');
    const std::string kind = line.substr(0, space);
    const std::string rest = space == std::string::npos ? "" : line.substr(space + 1);
    if (kind == "setting") {
      const size_t split = rest.find(' ');
      saved[rest.substr(0, split)] = split == std::string::npos ? "" : rest.substr(split + 1);
    } else if (kind == "frames_done") {
      state.frames_done = int(parseHexDouble(rest, path));
    } else if (kind == "lost") {
      state.lost.push_back(rest);
    } else if (kind == "pose") {
      std::istringstream fields(rest);
      std::string field;
      std::vector<double> v;
      while (fields >> field) v.push_back(parseHexDouble(field, path));
      if (v.size() != 17) throw Error("checkpoint " + path + ": malformed pose line");
      StampedPose p;
      p.timestamp = v[0];
      for (int i = 0; i < 16; ++i) p.T_world_cam.matrix().data()[i] = v[size_t(i) + 1];
      state.trajectory.push_back(p);
    } else {
      throw Error("checkpoint " + path + ": unexpected line '" + line + "'");
    }
  }
  for (const auto& [key, value] : settings) {
    const auto it = saved.find(key);
    const std::string before = it == saved.end() ? "(unset)" : it->second;
    if (before != value)
      throw Error("checkpoint " + path + " belongs to a run with " + key + " = " + before + ", this run has " + key +
                  " = " + value + "; resume with the same dataset and options, or start again with --force");
  }
  if (state.frames_done < 0 || size_t(state.frames_done) != state.trajectory.size())
    throw Error("checkpoint " + path + ": frame count and trajectory disagree");
  return state;
}

// What must not change between a run and its resumption (the pipeline state checks the volume
// and camera again, bit for bit).
Settings runSettings(const ReconstructOptions& o, const FrameSource& source, int frames, const PipelineParams& params,
                     Device device) {
  std::error_code ec;
  const std::filesystem::path dataset = std::filesystem::weakly_canonical(o.dataset, ec);
  char volume[160];
  std::snprintf(volume, sizeof volume, "%dx%dx%d@%a,%a", params.volume.dims.x, params.volume.dims.y,
                params.volume.dims.z, params.volume.voxel_size_m, params.volume.truncation_m);
  return {{"dataset", ec ? o.dataset : dataset.string()},
          {"dataset_frames", std::to_string(source.size())},
          {"frames", std::to_string(frames)},
          {"volume", volume},
          {"device", deviceName(device)},
          {"poses", o.poses},
          {"format", o.source.format},
          {"min_confidence", std::to_string(o.source.min_confidence)},
          {"intrinsics", o.intrinsics},
          {"labels", o.labels_dir},
          {"classes", o.classes_file},
          {"dynamic_classes", o.dynamic_classes},
          {"mask_dilation_px", o.mask_dilation_px ? std::to_string(*o.mask_dilation_px) : ""},
          {"labels_missing", o.labels_missing},
          {"class_vote", o.class_vote + ":" + std::to_string(o.class_vote_seed)}};
}

void checkOutputs(const ReconstructOptions& o) {
  if (o.output.empty() && !o.bench) throw Error("reconstruct: give an output scene with -o scene.vdb");
  if ((o.checkpoint_every > 0 || o.resume) && o.output.empty())
    throw Error("--checkpoint-every and --resume need -o scene.vdb (the checkpoint is written beside it)");
  if (o.checkpoint_every < 0) throw Error("--checkpoint-every " + std::to_string(o.checkpoint_every) + ": expected frames > 0");
  requireParentFolder(o.output, "-o");
  requireParentFolder(o.trajectory, "--trajectory");
  requireParentFolder(o.video, "--video");
  if (o.resume) {
    if (o.force) throw Error("--resume continues an interrupted run and --force starts a new one; choose one");
    if (!o.video.empty()) throw Error("--video cannot be continued by --resume; leave it out (--renders can)");
    if (!std::filesystem::exists(checkpointPath(o)))
      throw Error("--resume: " + checkpointPath(o) + " does not exist (the run finished, or was started without -o " +
                  o.output + ")");
    return;  // the outputs are the interrupted run's: they will be replaced
  }
  if (!o.output.empty() && std::filesystem::exists(checkpointPath(o)) && !o.force)
    throw Error(checkpointPath(o) + " holds an interrupted run; pass --resume to continue it or --force to start over");
  refuseOverwrite(o.output, o.force);
  refuseOverwrite(o.trajectory, o.force);
  refuseOverwrite(o.video, o.force);
  if (hasRenders(o.renders_dir) && !o.force)
    throw Error("--renders " + o.renders_dir + " already holds frame_*.png renders; pass --force to overwrite them");
}

// A run killed while writing leaves ".<name>.tmp<pid>..." beside its outputs (never a partial
// output); the next run of the same outputs removes them.
void removeStaleTempFiles(const std::vector<std::string>& outputs) {
  for (const std::string& output : outputs) {
    if (output.empty()) continue;
    const std::filesystem::path target(output);
    const std::filesystem::path dir = target.has_parent_path() ? target.parent_path() : ".";
    const std::string prefix = "." + target.filename().string() + ".tmp";
    std::error_code ec;
    for (const auto& entry : std::filesystem::directory_iterator(dir, ec))
      if (entry.path().filename().string().rfind(prefix, 0) == 0) std::filesystem::remove(entry.path(), ec);
  }
}

// Device bytes besides the volume: per brick a stamp and two list entries; per pixel the frame,
// its three-level pyramids and the model prediction (about 100 bytes, rounded up); and room for
// the reduction scratch and the runtime's own allocations.
constexpr uint64_t kGpuBytesPerBrick = 12;
constexpr uint64_t kGpuBytesPerPixel = 128;
constexpr uint64_t kGpuHeadroomBytes = uint64_t(64) << 20;

void checkMemory(const PipelineParams& params, bool with_labels, Device device, const Intrinsics& intrinsics,
                 bool quiet) {
  const VolumeSpec& v = params.volume;
  const uint64_t bricks = uint64_t(v.dims.x / kBrickSize) * (v.dims.y / kBrickSize) * (v.dims.z / kBrickSize);
  const uint64_t volume_bytes = uint64_t(v.voxelCount()) * DenseVolume::bytesPerVoxel(with_labels);
  char description[96];
  std::snprintf(description, sizeof description, "%dx%dx%d voxels%s", v.dims.x, v.dims.y, v.dims.z,
                with_labels ? " with classes" : "");
  // The host volume exists on both backends (on CUDA as the download target of the scene).
  if (const std::optional<HostMemory> memory = readHostMemory()) {
    const std::string warning = checkVolumeFits(volume_bytes + bricks * 4, *memory, description);
    if (!warning.empty() && !quiet) std::fprintf(stderr, "%s\n", warning.c_str());
  }
  GpuMemory gpu;
  if (resolveDevice(device) == Device::Cuda && cudaMemoryInfo(gpu.free_bytes, gpu.total_bytes)) {
    const uint64_t pixels = uint64_t(intrinsics.width) * uint64_t(intrinsics.height);
    checkVolumeFitsGpu(volume_bytes + bricks * kGpuBytesPerBrick + pixels * kGpuBytesPerPixel + kGpuHeadroomBytes,
                       gpu, description);
  }
}

void runReconstruct(const ReconstructOptions& o) {
  checkOutputs(o);
  removeStaleTempFiles({o.output, o.trajectory, o.output.empty() ? "" : checkpointPath(o)});
  SourceOptions source_options = o.source;
  if (!o.intrinsics.empty()) source_options.intrinsics = o.intrinsics;
  std::unique_ptr<FrameSource> source = openFrameSource(o.dataset, source_options);
  const bool with_labels = !o.labels_dir.empty();
  if (!with_labels && (!o.classes_file.empty() || !o.dynamic_classes.empty()))
    throw Error("--classes and --dynamic-classes need --labels DIR (per-frame label maps)");
  LabeledFrameSource* labeled = nullptr;
  std::vector<int> dynamic_ids;
  if (with_labels) {
    ClassTable classes = loadClassTable(o);
    if (!o.dynamic_classes.empty()) dynamic_ids = resolveClassList(classes, o.dynamic_classes, "--dynamic-classes");
    auto wrapped = std::make_unique<LabeledFrameSource>(std::move(source), o.labels_dir, std::move(classes),
                                                        parseMissingLabels(o.labels_missing));
    labeled = wrapped.get();
    source = std::move(wrapped);
  }
  const int frames = o.max_frames > 0 ? std::min(o.max_frames, source->size()) : source->size();
  if (frames == 0) throw Error(o.dataset + ": the sequence has no frames");

  PipelineParams params;
  params.volume.dims = parseVolumeSize(o.volume_size);
  const int largest = std::max({params.volume.dims.x, params.volume.dims.y, params.volume.dims.z});
  params.volume.voxel_size_m = o.voxel_size_m > 0 ? o.voxel_size_m : 3.0f / float(largest);
  params.volume.truncation_m = o.truncation_m;
  if (o.mask_dilation_px) {
    if (*o.mask_dilation_px < 0 || *o.mask_dilation_px > 64)
      throw Error("--mask-dilation-px " + std::to_string(*o.mask_dilation_px) + ": expected 0..64 pixels");
    params.dynamic_mask_dilation_px = *o.mask_dilation_px;
  }
  params.integration.class_vote = parseClassVote(o.class_vote);
  params.integration.class_vote_seed = o.class_vote_seed;
  const PoseSource pose_source = parsePoses(o.poses);
  params.volume.validate();
  checkMemory(params, with_labels, parseDevice(o.device), source->depthIntrinsics(), o.quiet);
  Pipeline pipeline(params, source->depthIntrinsics(), parseDevice(o.device), with_labels);
  if (!dynamic_ids.empty()) pipeline.setDynamicClasses(dynamic_ids);
  if (!o.quiet)
    std::fprintf(stderr, "%s: %d frames, %dx%d, volume %dx%dx%d at %.2f mm (%.2f m), device %s\n",
                 source->description().c_str(), frames, source->depthIntrinsics().width,
                 source->depthIntrinsics().height, params.volume.dims.x, params.volume.dims.y,
                 params.volume.dims.z, params.volume.voxel_size_m * 1000.f,
                 params.volume.voxel_size_m * largest, deviceName(pipeline.device()).c_str());

  const Settings settings = runSettings(o, *source, frames, pipeline.params(), pipeline.device());
  Trajectory trajectory;
  std::vector<std::string> lost;
  int first = 0;
  if (o.resume) {
    std::string text;
    restorePipelineState(pipeline, checkpointPath(o), &text);
    ResumeState state = parseAnnotations(text, settings, checkpointPath(o));
    if (state.frames_done > frames || state.frames_done != pipeline.framesProcessed())
      throw Error("checkpoint " + checkpointPath(o) + " is past the end of this run (" +
                  std::to_string(state.frames_done) + " of " + std::to_string(frames) + " frames)");
    first = state.frames_done;
    trajectory = std::move(state.trajectory);
    lost = std::move(state.lost);
    if (!o.quiet) std::fprintf(stderr, "resuming after frame %d of %d from %s\n", first, frames, checkpointPath(o).c_str());
  } else if (!o.output.empty()) {
    std::filesystem::remove(checkpointPath(o));  // --force: a stale checkpoint must not be resumed later
  }

  SceneMetadata meta;
  meta.source = o.dataset;
  meta.software_version = VDBFUSE_VERSION_STRING;
  if (labeled) meta.classes = labeled->classes();
  // Trajectory, scene and checkpoint of the first `done` frames, each written atomically.
  auto writeOutputs = [&](int done, bool with_checkpoint) {
    if (!o.trajectory.empty()) writeTumTrajectory(o.trajectory, trajectory);
    if (o.output.empty()) return;
    meta.frame_count = done - pipeline.framesLost();
    writeScene(sceneFromDenseVolume(pipeline.hostVolume(), meta), o.output);
    if (with_checkpoint)
      savePipelineState(pipeline, checkpointPath(o), makeAnnotations(settings, done, lost, trajectory));
  };

  // --bench decodes everything first so the timings hold the four stages only.
  std::vector<RgbdFrame> preloaded;
  if (o.bench)
    for (int i = first; i < frames; ++i) preloaded.push_back(source->load(i));

  std::unique_ptr<VideoWriter> video;
  if (!o.renders_dir.empty()) std::filesystem::create_directories(o.renders_dir);
  StopSignals stop;
  int stop_signal = 0;
  int done = first;
  ProgressBar progress(frames, !o.quiet);
  const auto start = std::chrono::steady_clock::now();
  FramePrefetcher prefetcher(*source, first, o.bench ? 0 : frames - first);
  for (int i = first; i < frames; ++i) {
    RgbdFrame frame = o.bench ? std::move(preloaded[size_t(i - first)]) : std::move(*prefetcher.next());
    const FrameResult result = pipeline.processFrame(frame, pose_source);
    trajectory.push_back({frame.timestamp, result.T_world_cam});
    if (!result.tracked) lost.push_back(frame.name + ": " + result.lost_reason);
    if (!o.renders_dir.empty() || !o.video.empty()) {
      const Prediction prediction = pipeline.predict(true);
      const ColorImage panel = composeRenderPanel(frame, prediction, pipeline.pose());
      if (!o.renders_dir.empty()) {
        char name[32];
        std::snprintf(name, sizeof(name), "frame_%05d.png", i);
        writeColorPng((std::filesystem::path(o.renders_dir) / name).string(), panel);
      }
      if (!o.video.empty()) {
        if (!video) video = std::make_unique<VideoWriter>(o.video, panel.width(), panel.height(), 30.0);
        video->write(panel);
      }
    }
    done = i + 1;
    progress.update(done, lost.empty() ? "" : std::to_string(lost.size()) + " lost");
    if ((stop_signal = stop.received()) != 0) break;
    if (o.checkpoint_every > 0 && done % o.checkpoint_every == 0 && done < frames) writeOutputs(done, true);
  }
  progress.finish();
  const double wall_s = std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
  if (video) video->close();

  if (stop_signal != 0 && done < frames) {
    std::fprintf(stderr, "\n%s: stopping after frame %d of %d\n", StopSignals::name(stop_signal).c_str(), done, frames);
    writeOutputs(done, true);
    if (!o.output.empty())
      std::fprintf(stderr, "wrote %s%s and %s (%d frames); continue with the same command and --resume\n",
                   o.output.c_str(), o.trajectory.empty() ? "" : (", " + o.trajectory).c_str(),
                   checkpointPath(o).c_str(), done);
    throw ExitWithStatus(StopSignals::exitStatus(stop_signal), "interrupted");
  }

  std::printf("tracked %d of %d frames", frames - pipeline.framesLost(), frames);
  if (!lost.empty()) {
    std::printf("; %zu lost (last good pose kept, not integrated):\n", lost.size());
    for (const std::string& l : lost) std::printf("  %s\n", l.c_str());
  } else {
    std::printf("\n");
  }
  if (labeled) printLabelSummary(labeled->stats(), labeled->classes(), frames);
  printTimingTable(pipeline.timer(), frames - first, wall_s);

  if (!o.trajectory.empty()) writeTumTrajectory(o.trajectory, trajectory);
  if (!o.output.empty()) {
    const auto t0 = std::chrono::steady_clock::now();
    meta.frame_count = frames - pipeline.framesLost();
    Scene scene = sceneFromDenseVolume(pipeline.hostVolume(), meta);
    const SceneUp up = setSceneFrame(scene, trajectory, *source);  // gravity and camera, for exports (scene_frame.h)
    std::printf("up: %s (%s)\n", up.source.c_str(), up.detail.c_str());
    writeScene(scene, o.output);
    std::filesystem::remove(checkpointPath(o));  // the run is complete: nothing to resume
    std::printf("wrote %s (%zu active voxels) in %.2f s\n", o.output.c_str(), scene.activeVoxelCount(),
                std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count());
  }
}

void setup(CLI::App& root) {
  auto o = std::make_shared<ReconstructOptions>();
  CLI::App* cmd = root.add_subcommand("reconstruct", "Fuse an RGB-D sequence into a scene (.vdb)");
  cmd->add_option("dataset", o->dataset, "TUM folder, Record3D .r3d file or Record3D export folder")->required();
  cmd->add_option("-o,--output", o->output, "Scene file to write (.vdb)");
  cmd->add_option("--trajectory", o->trajectory,
                  "Camera trajectory to write (TUM format; default: the scene's path with .txt)");
  cmd->add_option("--volume-size", o->volume_size, "Voxels: N or X,Y,Z (multiples of 8)")->capture_default_str();
  cmd->add_option("--voxel-size-m", o->voxel_size_m, "Voxel edge in metres (default: 3 m / largest dimension)");
  cmd->add_option("--truncation-m", o->truncation_m, "TSDF truncation in metres (default: 5 voxels)");
  cmd->add_option("--max-frames", o->max_frames, "Fuse at most this many frames");
  cmd->add_option("--device", o->device, "cpu, cuda or auto (CUDA when a GPU is usable)")->capture_default_str();
  cmd->add_option("--poses", o->poses, "icp, given (recorded poses) or given+icp (refine them)")->capture_default_str();
  cmd->add_option("--intrinsics", o->intrinsics, "fx,fy,cx,cy overriding the dataset's calibration");
  cmd->add_option("--format", o->source.format, "auto, tum, r3d or r3d-export")->capture_default_str();
  cmd->add_option("--min-confidence", o->source.min_confidence, "Record3D: lowest depth confidence kept (0-2)")
      ->capture_default_str();
  cmd->add_option("--labels", o->labels_dir,
                  "Folder of per-frame label maps (8/16-bit PNG class ids, by file stem or frame index)");
  cmd->add_option("--classes", o->classes_file, "Class table JSON for --labels (default: DIR/classes.json); label ids it does not name are fused as "
                  "unknown and reported");
  cmd->add_option("--dynamic-classes", o->dynamic_classes,
                  "Classes kept out of tracking and geometry (names or ids, e.g. person)");
  cmd->add_option("--mask-dilation-px", o->mask_dilation_px,
                  "Grow dynamic-class masks by this many pixels (default 4)");
  cmd->add_option("--labels-missing", o->labels_missing,
                  "A frame without a label map: skip (fuse it without labels) or error")
      ->capture_default_str();
  cmd->add_option("--class-vote", o->class_vote, "majority or probabilistic class fusion")->capture_default_str();
  cmd->add_option("--class-vote-seed", o->class_vote_seed, "Seed of --class-vote probabilistic")
      ->capture_default_str();
  cmd->add_option("--renders", o->renders_dir, "Write input | predicted color | shaded model PNGs per frame here");
  cmd->add_option("--video", o->video, "Write the same panels as an MP4 video");
  cmd->add_flag("--bench", o->bench, "Decode all frames first, then time the fusion stages alone");
  cmd->add_flag("-q,--quiet", o->quiet, "No progress bar");
  cmd->add_flag("-f,--force", o->force, "Overwrite existing outputs");
  cmd->add_option("--checkpoint-every", o->checkpoint_every,
                  "Every N frames write the scene, the trajectory and OUTPUT.checkpoint (to --resume from); "
                  "SIGINT/SIGTERM always finish the frame and write them");
  cmd->add_flag("--resume", o->resume,
                "Continue an interrupted run from OUTPUT.checkpoint (same dataset and options)");
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
