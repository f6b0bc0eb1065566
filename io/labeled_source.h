#pragma once
// Attaches per-frame label maps (a LabelMapDir) to any FrameSource, so semantic fusion works the
// same for TUM folders and Record3D captures. Ids are checked against a class table: ids the
// table does not name become kUnknownLabel (0xFFFF, not voted) and are counted, not guessed.
#include <atomic>
#include <map>
#include <memory>
#include <mutex>
#include <string>
#include <vector>

#include "core/class_table.h"
#include "core/frame.h"
#include "io/label_maps.h"

namespace vf {

// The label value fusion treats as "no class" (fusion/volume.h kUnknownClass).
constexpr uint16_t kUnknownLabel = 0xFFFF;

enum class MissingLabels {
  Skip,   // the frame is fused without labels (geometry only; no dynamic mask)
  Error,  // load() throws vf::Error naming the missing file
};

// Parses "skip" / "error"; throws vf::Error otherwise.
MissingLabels parseMissingLabels(const std::string& text);

// What the label maps held, for the summary after fusion.
struct LabelStats {
  int frames_labelled = 0;
  std::vector<std::string> missing_files;   // sorted by frame index
  std::map<int, long long> unknown_id_pixels;  // id not in the class table -> pixels (at depth res.)
};

class LabeledFrameSource : public FrameSource {
 public:
  // `inner` supplies the frames; maps come from `folder`, matched by the frame's name (file stem)
  // first, else by its index, and are resampled (nearest) to the depth resolution.
  LabeledFrameSource(std::unique_ptr<FrameSource> inner, const std::string& folder, ClassTable classes,
                     MissingLabels missing);

  int size() const override { return inner_->size(); }
  RgbdFrame load(int index) const override;  // thread-safe
  Intrinsics depthIntrinsics() const override { return inner_->depthIntrinsics(); }
  Distortion depthDistortion() const override { return inner_->depthDistortion(); }
  std::string description() const override;
  Trajectory groundTruth() const override { return inner_->groundTruth(); }
  bool colorRegisteredToDepth() const override { return inner_->colorRegisteredToDepth(); }
  std::optional<float> depthNoiseQuadratic() const override { return inner_->depthNoiseQuadratic(); }
  std::optional<Vec3f> worldUp() const override { return inner_->worldUp(); }

  const ClassTable& classes() const { return classes_; }
  // Totals over every load() so far.
  LabelStats stats() const;

 private:
  std::unique_ptr<FrameSource> inner_;
  LabelMapDir dir_;
  ClassTable classes_;
  MissingLabels missing_;
  std::vector<uint8_t> known_;  // 65536 entries: 1 when the table names the id
  mutable std::mutex mutex_;
  mutable LabelStats stats_;
  mutable std::map<int, std::string> missing_by_index_;
};

}  // namespace vf
