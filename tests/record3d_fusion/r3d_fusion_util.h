#pragma once
// Fusing the shared Record3D capture in tests and evaluation tools.
#include <memory>
#include <string>
#include <vector>

#include "core/frame.h"
#include "fusion/pipeline.h"
#include "io/class_table_io.h"
#include "io/labeled_source.h"
#include "io/record3d_export.h"

namespace vf::test {

// 1 cm voxels: the room at the detail the tests need, fast.
inline PipelineParams roomParams(float voxel_m = 0.01f) {
  PipelineParams p;
  p.volume.voxel_size_m = voxel_m;
  return p;
}

// The capture, with the person masks attached when `labels_dir` is not empty.
inline std::unique_ptr<FrameSource> openDance(const std::string& capture, const std::string& labels_dir,
                                              const std::string& classes_json, int min_confidence = 2) {
  Record3dOptions options;
  options.min_confidence = min_confidence;
  std::unique_ptr<FrameSource> source = openRecord3d(capture, options);
  if (labels_dir.empty()) return source;
  return std::make_unique<LabeledFrameSource>(std::move(source), labels_dir, readClassTable(classes_json),
                                              MissingLabels::Error);
}

}  // namespace vf::test
