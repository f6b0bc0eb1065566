// vdbfuse convert: rewrite any input `reconstruct` reads (TUM, 7-Scenes/3DMatch, Replica, ScanNet,
// Redwood, a Record3D .r3d capture or export) as a TUM RGB-D folder, so that it can be inspected
// and used by TUM tools.
#include <cstdio>
#include <memory>
#include <string>

#include "app/command_registry.h"
#include "app/open_source.h"
#include "app/output_policy.h"
#include "app/usage_errors.h"
#include "core/error.h"
#include "io/tum_writer.h"

namespace vf::app {
namespace {

struct ConvertOptions {
  std::string input;
  std::string to = "tum";
  std::string output;
  SourceOptions source;
  int max_frames = -1;
  bool force = false;
};

void runConvert(const ConvertOptions& o) {
  OutputPolicy outputs(o.force);
  outputs.input(o.input);
  outputs.folder(o.output, "output");
  // The same reader `reconstruct` uses, so what converts is what would be fused.
  const std::unique_ptr<FrameSource> source = openFrameSource(o.input, o.source);
  std::fprintf(stderr, "reading %s\n", source->description().c_str());
  if (!source->colorRegisteredToDepth())
    std::fprintf(stderr,
                 "warning: the colour of this input is not registered to its depth; the TUM folder pairs them "
                 "pixel for pixel as they are, resized to the depth size\n");

  TumWriteOptions write;
  write.max_frames = o.max_frames;
  int last_decile = -1;
  write.progress = [&last_decile](int done, int total) {
    const int decile = total ? done * 10 / total : 10;
    if (decile != last_decile) {
      last_decile = decile;
      std::fprintf(stderr, "  %d/%d frames\n", done, total);
    }
  };
  TumWriteResult result;
  try {
    result = writeTumFolder(*source, o.output, write);
  } catch (const Error& e) {  // name the folder asked for, not the temporary one being filled
    throw Error("cannot write " + o.output + " (the old folder, if any, is kept): " + e.what());
  }
  std::printf("wrote %d frames and %d poses to %s (TUM: depth/ rgb/ rgb.txt depth.txt%s "
              "camera_intrinsics.txt)\n",
              result.frames, result.poses, o.output.c_str(),
              result.poses ? " groundtruth.txt" : "");
}

void setupConvertCommand(CLI::App& root) {
  auto options = std::make_shared<ConvertOptions>();
  CLI::App* cmd = root.add_subcommand(
      "convert", "Convert any input reconstruct reads (TUM, 7-Scenes, Replica, ScanNet, Redwood, Record3D) into a "
                 "TUM RGB-D folder");
  cmd->add_option("input", options->input, std::string("RGB-D input, detected from its files:\n") + kKnownLayouts)
      ->required();
  cmd->add_option("output", options->output, "output folder (must not exist unless --force)")
      ->required();
  cmd->add_option("--to", options->to, "output format")
      ->capture_default_str()
      ->check(CLI::IsMember({"tum"}));
  cmd->add_option("--format", options->source.format, "auto, tum, r3d, r3d-export, 7scenes, replica, scannet or redwood")
      ->capture_default_str();
  cmd->add_option("--intrinsics", options->source.intrinsics, "fx,fy,cx,cy overriding the input's calibration");
  cmd->add_option("--depth-scale", options->source.depth_units_per_metre,
                  "Depth units per metre, overriding the input's own (1000 = mm, 5000 = TUM, 6553.5 = Replica)");
  cmd->add_option("--min-confidence", options->source.min_confidence,
                  "Record3D: drop depth whose ARKit confidence (0 low, 1 medium, 2 high) is below this")
      ->capture_default_str()
      ->check(inRange(0, 2));
  cmd->add_option("--max-frames", options->max_frames, "convert only the first N frames")
      ->check(atLeast(1));
  cmd->add_flag("-f,--force", options->force, "replace an existing output folder, with everything in it");
  cmd->callback([options] { runConvert(*options); });
}

}  // namespace

VF_REGISTER_COMMAND(60, setupConvertCommand);

}  // namespace vf::app
