// vdbfuse convert: rewrite a Record3D capture (.r3d or EXR+JPG export folder) as a TUM RGB-D
// folder, so the iPhone data can be inspected and used by TUM tools.
#include <cstdio>
#include <memory>
#include <string>

#include "app/command_registry.h"
#include "app/output_policy.h"
#include "app/usage_errors.h"
#include "core/error.h"
#include "io/record3d_export.h"
#include "io/tum_writer.h"

namespace vf::app {
namespace {

struct ConvertOptions {
  std::string capture;
  std::string format = "tum";
  std::string output;
  int min_confidence = 2;
  int max_frames = -1;
  bool force = false;
};

void runConvert(const ConvertOptions& o) {
  OutputPolicy outputs(o.force);
  outputs.input(o.capture);
  outputs.folder(o.output, "output");
  Record3dOptions r3d;
  r3d.min_confidence = o.min_confidence;
  const std::unique_ptr<FrameSource> source = openRecord3d(o.capture, r3d);
  std::fprintf(stderr, "reading %s\n", source->description().c_str());

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
      "convert", "Convert a Record3D capture (.r3d or EXR+JPG export) into a TUM RGB-D folder");
  cmd->add_option("capture", options->capture, "Record3D .r3d file, the folder it unzips to, or an export folder (metadata.json)")
      ->required();
  cmd->add_option("output", options->output, "output folder (must not exist unless --force)")
      ->required();
  cmd->add_option("--to", options->format, "output format")
      ->capture_default_str()
      ->check(CLI::IsMember({"tum"}));
  cmd->add_option("--min-confidence", options->min_confidence,
                  "drop depth whose ARKit confidence (0 low, 1 medium, 2 high) is below this")
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
