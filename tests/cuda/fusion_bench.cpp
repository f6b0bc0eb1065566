// fusion_bench: the four fusion stages alone on a TUM folder or on the synthetic room scan, as
// `vdbfuse reconstruct --bench` times them (every frame decoded or rendered first, then per-stage
// wall clock from the pipeline's StageTimer), and the tracked trajectory's ATE against the
// ground truth.
//
// The GPU bundle's benchmark (scripts/gpu_bundle.sh, cuda/README.md): it links only core, fusion,
// the CUDA backend, io's frame readers and the room's renderer (no OpenCV, OpenVDB or VTK), so
// that it can be carried to a GPU machine in a few MiB. Its use of the Pipeline is the few lines
// of runFrames().
//
//   fusion_bench TUM_FOLDER|--synthetic-room [--device cpu|cuda|auto] [--max-frames N]
//                [--trajectory FILE] [--timings FILE.csv] [--voxel-size-m M] [--leave-gpu-mib N]
//                [--end-to-end]
//   --end-to-end: decode the frames while fusing, on as many threads as `vdbfuse reconstruct`
//                gives the device (FramePrefetcher::workersFor), and time the whole loop:
//                frames/s with decoding included (issue 40's acceptance 3 compares the backends so).
//   --synthetic-room: the 8 x 6 m room of samples/synthetic_room (300 frames, a full turn,
//                Kinect noise), rendered in memory: issue 12's large scene, with nothing to carry.
//   --leave-gpu-mib N: before fusing, occupy all of the GPU's free memory but N MiB, so that the
//                start-up check (too little to start) or the brick pool's growth (the volume
//                fills up, the run stops and says so) meet a full GPU on purpose.
//   fusion_bench --gpu-info     says whether a CUDA GPU is usable, and why not (exit 3 then)
//
// Besides the table, one line "summary: stage=ms ... frame_ms=... ate_cm=..." for scripts.
// Exit status: 0 done, 1 error (the message names the file or the limit), 2 bad arguments.
#include <algorithm>
#include <chrono>
#include <cstdio>
#include <cstdlib>
#include <fstream>
#include <memory>
#include <optional>
#include <string>
#include <vector>

#include "app/memory_check.h"
#include "core/atomic_output.h"
#include "core/error.h"
#include "fusion/cuda_api.h"
#include "fusion/device.h"
#include "fusion/frame_prefetcher.h"
#include "fusion/pipeline.h"
#include "io/trajectory_io.h"
#include "io/trajectory_metrics.h"
#include "io/tum_dataset.h"
#include "room_source.h"

#include <tbb/parallel_for.h>

namespace {

using Clock = std::chrono::steady_clock;

double msSince(Clock::time_point start) {
  return std::chrono::duration<double, std::milli>(Clock::now() - start).count();
}

struct Options {
  bool gpu_info = false;
  std::string dataset;
  bool synthetic_room = false;
  std::string device = "auto";
  int max_frames = 0;
  std::string trajectory;
  std::string timings;
  float voxel_size_m = 0;   // 0: PipelineParams' default
  int leave_gpu_mib = -1;   // < 0: leave the GPU alone
  bool end_to_end = false;
};

struct UsageError : vf::Error {
  using vf::Error::Error;
};

Options parseArguments(int argc, char** argv) {
  Options o;
  for (int i = 1; i < argc; ++i) {
    const std::string arg = argv[i];
    auto value = [&]() -> std::string {
      if (i + 1 >= argc) throw UsageError(arg + " needs a value");
      return argv[++i];
    };
    if (arg == "--gpu-info") o.gpu_info = true;
    else if (arg == "--synthetic-room") o.synthetic_room = true;
    else if (arg == "--device") o.device = value();
    else if (arg == "--max-frames") o.max_frames = std::atoi(value().c_str());
    else if (arg == "--trajectory") o.trajectory = value();
    else if (arg == "--timings") o.timings = value();
    else if (arg == "--voxel-size-m") o.voxel_size_m = std::strtof(value().c_str(), nullptr);
    else if (arg == "--leave-gpu-mib") o.leave_gpu_mib = std::atoi(value().c_str());
    else if (arg == "--end-to-end") o.end_to_end = true;
    else if (!arg.empty() && arg[0] == '-') throw UsageError("unknown option " + arg);
    else if (o.dataset.empty()) o.dataset = arg;
    else throw UsageError("one TUM folder only, got " + o.dataset + " and " + arg);
  }
  if (o.dataset.empty() == !o.synthetic_room && !o.gpu_info) throw UsageError("give one of a TUM folder and --synthetic-room");
  if (o.max_frames < 0) throw UsageError("--max-frames must be >= 0");
  return o;
}

// The check `vdbfuse reconstruct` makes before the CUDA backend allocates (app/memory_check.h):
// the frame buffers and the first brick pool must fit in the free memory, else a vf::Error says
// how much is needed and free.
void checkGpuMemory(const vf::Intrinsics& k) {
  uint64_t free_bytes = 0, total_bytes = 0;
  if (!vf::cudaMemoryInfo(free_bytes, total_bytes)) return;
  vf::app::checkFitsGpu(vf::Pipeline::startupDeviceBytes(k, false), {free_bytes, total_bytes},
                        "fusing " + std::to_string(k.width) + "x" + std::to_string(k.height) + " frames");
}

// Holds all of the GPU's free memory but `leave_mib` while it lives.
struct GpuOccupier {
  explicit GpuOccupier(int leave_mib) {
    uint64_t free_bytes = 0, total_bytes = 0;
    if (leave_mib < 0 || !vf::cudaMemoryInfo(free_bytes, total_bytes)) return;
    const uint64_t leave = uint64_t(leave_mib) << 20;
    if (free_bytes > leave) block = vf::cuda::allocate(size_t(free_bytes - leave));
    std::printf("occupied %.1f GiB of the GPU, %d MiB left free\n", double(free_bytes - leave) / double(1ull << 30),
                leave_mib);
  }
  ~GpuOccupier() {
    if (block) vf::cuda::release(block);
  }
  void* block = nullptr;
};

struct RunResult {
  vf::Trajectory trajectory;
  std::vector<double> frame_ms;  // processFrame wall clock, per frame
  int volume_full_after = 0;     // frames done when memory for bricks ran out (0: it never did)
  double loop_ms = 0;            // the whole loop (with --end-to-end: decoding included)
};

// Fuses one frame into r; false when the volume is full (the run stops there).
bool fuseFrame(vf::Pipeline& pipeline, const vf::RgbdFrame& frame, RunResult& r) {
  const Clock::time_point start = Clock::now();
  const vf::FrameResult result = pipeline.processFrame(frame, vf::PoseSource::Icp);
  r.frame_ms.push_back(msSince(start));
  r.trajectory.push_back({frame.timestamp, result.T_world_cam});
  if (!result.volume_full) return true;
  r.volume_full_after = int(r.trajectory.size());
  return false;
}

RunResult runFrames(vf::Pipeline& pipeline, const std::vector<vf::RgbdFrame>& frames) {
  RunResult r;
  const Clock::time_point start = Clock::now();
  for (const vf::RgbdFrame& frame : frames)
    if (!fuseFrame(pipeline, frame, r)) break;
  r.loop_ms = msSince(start);
  return r;
}

// The same, decoding the frames meanwhile on `workers` threads, as reconstruct does.
RunResult runFramesDecoding(vf::Pipeline& pipeline, const vf::FrameSource& source, int frames, int workers) {
  RunResult r;
  const Clock::time_point start = Clock::now();
  vf::FramePrefetcher prefetcher(source, 0, frames, vf::FramePrefetcher::kDefaultDepth, workers);
  while (std::optional<vf::RgbdFrame> frame = prefetcher.next())
    if (!fuseFrame(pipeline, *frame, r)) break;
  r.loop_ms = msSince(start);
  return r;
}

double median(std::vector<double> v) {
  if (v.empty()) return 0;
  std::sort(v.begin(), v.end());
  const size_t n = v.size();
  return n % 2 ? v[n / 2] : 0.5 * (v[n / 2 - 1] + v[n / 2]);
}

void writeTimings(const std::string& path, const vf::StageTimer& timer, const std::vector<double>& frame_ms) {
  std::string csv = "frame";
  for (const std::string& stage : timer.stages()) csv += "," + stage + "_ms";
  csv += ",frame_ms\n";
  for (size_t i = 0; i < frame_ms.size(); ++i) {
    csv += std::to_string(i);
    for (const std::string& stage : timer.stages()) {
      const std::vector<double>& s = timer.samples(stage);
      // "track" has no sample for the first frame (nothing to track against yet).
      const size_t offset = frame_ms.size() - s.size();
      csv += i >= offset ? "," + std::to_string(s[i - offset]) : ",";
    }
    csv += "," + std::to_string(frame_ms[i]) + "\n";
  }
  vf::writeFileAtomic(path, csv);
}

int gpuInfo() {
  if (!vf::cudaBuilt()) {
    std::printf("no CUDA GPU: this build has no CUDA backend\n");
    return 3;
  }
  const int count = vf::cudaDeviceCount();
  if (count == 0) {
    std::printf("no CUDA GPU: %s\n", vf::cuda::lastErrorDescription().c_str());
    return 3;
  }
  uint64_t free_bytes = 0, total_bytes = 0;
  vf::cudaMemoryInfo(free_bytes, total_bytes);
  std::printf("CUDA GPUs: %d; device 0 has %.1f GiB free of %.1f GiB\n", count, double(free_bytes) / double(1ull << 30),
              double(total_bytes) / double(1ull << 30));
  return 0;
}

int run(const Options& o) {
  if (o.gpu_info) return gpuInfo();
  std::unique_ptr<vf::FrameSource> source;
  if (o.synthetic_room) source = std::make_unique<vf::synth::RoomScanSource>();
  else source = std::make_unique<vf::TumDataset>(o.dataset);
  const vf::FrameSource& dataset = *source;
  const int frames = o.max_frames > 0 ? std::min(o.max_frames, dataset.size()) : dataset.size();
  const vf::Device device = vf::resolveDevice(vf::parseDevice(o.device));

  vf::PipelineParams params;
  if (o.voxel_size_m > 0) params.volume.voxel_size_m = o.voxel_size_m;
  params.validate();
  const GpuOccupier occupier(device == vf::Device::Cuda ? o.leave_gpu_mib : -1);
  if (device == vf::Device::Cuda) checkGpuMemory(dataset.depthIntrinsics());

  const Clock::time_point decode_start = Clock::now();
  std::vector<vf::RgbdFrame> decoded;
  if (!o.end_to_end) {
    decoded.resize(static_cast<size_t>(frames));
    if (o.synthetic_room)  // rendered by ray casting: on every core (load() is thread-safe)
      tbb::parallel_for(0, frames, [&](int i) { decoded[size_t(i)] = dataset.load(i); });
    else
      for (int i = 0; i < frames; ++i) decoded[size_t(i)] = dataset.load(i);
  }
  const double decode_ms = msSince(decode_start);

  const Clock::time_point setup_start = Clock::now();
  vf::Pipeline pipeline(params, dataset.depthIntrinsics(), device);
  const double setup_ms = msSince(setup_start);
  const int workers = vf::FramePrefetcher::workersFor(device);  // as reconstruct
  const RunResult r = o.end_to_end ? runFramesDecoding(pipeline, dataset, frames, workers) : runFrames(pipeline, decoded);

  std::printf("%s\n", dataset.description().c_str());
  char decoding[160];
  if (o.end_to_end)
    std::snprintf(decoding, sizeof decoding, "%d frames decoded while fusing, on %d threads", frames, workers);
  else
    std::snprintf(decoding, sizeof decoding, "%d frames decoded in %.1f ms (%.2f ms per frame, not timed below)", frames,
                  decode_ms, decode_ms / std::max(frames, 1));
  std::printf("device %s, voxels of %.2f mm; pipeline set up in %.1f ms; %s; %d bricks (%.1f MiB)\n",
              vf::deviceName(device).c_str(), params.volume.voxel_size_m * 1000.f, setup_ms, decoding,
              pipeline.brickCount(), double(pipeline.volumeBytes()) / double(1 << 20));
  if (r.volume_full_after > 0)
    std::printf("volume full after frame %d: %d bricks (%.1f MiB) are all the memory allows\n", r.volume_full_after,
                pipeline.brickCount(), double(pipeline.volumeBytes()) / double(1 << 20));
  std::printf("%-10s %10s %10s %10s\n", "stage", "median ms", "mean ms", "max ms");
  const vf::StageTimer& timer = pipeline.timer();
  // The four stages in pipeline order ("track" first appears with the second frame), then any other.
  std::vector<std::string> stages;
  for (const char* stage : {"measure", "track", "integrate", "raycast"})
    if (std::count(timer.stages().begin(), timer.stages().end(), stage)) stages.push_back(stage);
  for (const std::string& stage : timer.stages())
    if (std::find(stages.begin(), stages.end(), stage) == stages.end()) stages.push_back(stage);
  double sum_medians = 0;
  for (const std::string& stage : stages) {
    const std::vector<double>& s = timer.samples(stage);
    std::printf("%-10s %10.3f %10.3f %10.3f\n", stage.c_str(), timer.median(stage), timer.mean(stage),
                *std::max_element(s.begin(), s.end()));
    sum_medians += timer.median(stage);
  }
  double frame_mean = 0;
  for (double ms : r.frame_ms) frame_mean += ms / double(r.frame_ms.size());
  std::printf("per frame: %.3f ms (sum of the stage medians, %.1f frames/s); processFrame median %.3f ms, mean %.3f ms\n",
              sum_medians, sum_medians > 0 ? 1000.0 / sum_medians : 0.0, median(r.frame_ms), frame_mean);
  const double loop_fps = r.loop_ms > 0 ? 1000.0 * double(r.frame_ms.size()) / r.loop_ms : 0.0;
  if (o.end_to_end)
    std::printf("end to end: %zu frames in %.2f s, %.1f frames/s (decoding on %d thread%s included)\n",
                r.frame_ms.size(), r.loop_ms / 1000.0, loop_fps, workers, workers == 1 ? "" : "s");
  std::printf("tracked %d of %d frames\n", frames - pipeline.framesLost(), frames);
  const vf::Trajectory truth = dataset.groundTruth();
  std::string ate_cm = "none";
  if (truth.empty()) {
    std::printf("ATE: no ground truth in %s\n", dataset.description().c_str());
  } else {
    try {
      const vf::AteResult ate = vf::computeAte(r.trajectory, truth);
      std::printf("ATE RMSE %.3f cm over %d poses (mean %.3f cm, max %.3f cm)\n", ate.rmse_m * 100, ate.pairs,
                  ate.mean_m * 100, ate.max_m * 100);
      char text[32];
      std::snprintf(text, sizeof text, "%.3f", ate.rmse_m * 100);
      ate_cm = text;
    } catch (const vf::Error& e) {  // too few frames within the ground truth's time span
      std::printf("ATE: not computed: %s\n", e.what());
    }
  }
  std::printf("summary: device=%s frames=%d", vf::deviceName(device).c_str(), frames);
  for (const std::string& stage : stages) std::printf(" %s=%.3f", stage.c_str(), timer.median(stage));
  std::printf(" frame_ms=%.3f fps=%.1f", sum_medians, sum_medians > 0 ? 1000.0 / sum_medians : 0.0);
  if (o.end_to_end) std::printf(" e2e_fps=%.1f decode_threads=%d", loop_fps, workers);
  std::printf(" tracked=%d ate_cm=%s\n", frames - pipeline.framesLost(), ate_cm.c_str());
  if (!o.trajectory.empty()) vf::writeTumTrajectory(o.trajectory, r.trajectory);
  if (!o.timings.empty()) writeTimings(o.timings, timer, r.frame_ms);
  return 0;
}

}  // namespace

int main(int argc, char** argv) {
  try {
    return run(parseArguments(argc, argv));
  } catch (const UsageError& e) {
    std::fprintf(stderr, "fusion_bench: %s\nusage: fusion_bench TUM_FOLDER|--synthetic-room [--device cpu|cuda|auto] [--max-frames N] "
                         "[--trajectory FILE] [--timings FILE.csv] [--voxel-size-m M] [--leave-gpu-mib N]\n", e.what());
    return 2;
  } catch (const vf::Error& e) {
    std::fprintf(stderr, "fusion_bench: %s\n", e.what());
    return 1;
  }
}
