#pragma once
// Opens whatever RGB-D input a path names: a TUM folder, a Record3D .r3d capture (or the folder
// it unzips to), a Record3D EXR+JPG export, a 7-Scenes/3DMatch frame folder, Replica (NICE-SLAM
// layout), a ScanNet export or a Redwood folder (detected from the files; `format` forces one).
#include <memory>
#include <optional>
#include <string>

#include <CLI/CLI.hpp>

#include "core/frame.h"

namespace vf::app {

struct SourceOptions {
  // auto | tum | r3d | r3d-export | 7scenes (= 3dmatch) | replica | scannet | redwood
  std::string format = "auto";
  std::optional<std::string> intrinsics;     // "fx,fy,cx,cy" override
  int min_confidence = 2;                    // Record3D depth confidence threshold
  std::optional<float> depth_units_per_metre;  // --depth-scale: overrides the reader's own
  std::string photometric = "auto";          // auto | on | off: the photometric ICP term
};

// What the formats are, for --help and for the error of an unknown layout.
extern const char* const kKnownLayouts;

// Opens the source and checks its depth scale on the first frame with readings: a median under
// 0.2 m or over 20 m is an error naming the folder, the scale and --depth-scale (a warning on
// stderr when the scale came from --depth-scale itself).
std::unique_ptr<FrameSource> openFrameSource(const std::string& path, const SourceOptions& options);

// Whether the photometric term should run on this source: --photometric on/off, or auto = on
// unless the source says its colour is not registered to depth. `note` gets a line for the user
// when auto turned it off.
bool photometricTermWanted(const SourceOptions& options, const FrameSource& source, std::string* note);

// Registers --depth-scale and --photometric on a command that reads a source.
void addDatasetOptions(CLI::App& cmd, SourceOptions& options);

// "depth_scale=...,photometric=...": what a resumed run must repeat.
std::string datasetOptionsKey(const SourceOptions& options);

}  // namespace vf::app
