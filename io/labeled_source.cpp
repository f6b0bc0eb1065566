#include "io/labeled_source.h"

#include "core/error.h"

namespace vf {

MissingLabels parseMissingLabels(const std::string& text) {
  if (text == "skip") return MissingLabels::Skip;
  if (text == "error") return MissingLabels::Error;
  throw Error("--labels-missing " + text + ": expected skip or error");
}

LabeledFrameSource::LabeledFrameSource(std::unique_ptr<FrameSource> inner, const std::string& folder,
                                       ClassTable classes, MissingLabels missing)
    : inner_(std::move(inner)), dir_(folder), classes_(std::move(classes)), missing_(missing), known_(65536, 0) {
  if (classes_.empty()) throw Error("label maps in " + folder + ": the class table is empty");
  for (const ClassInfo& c : classes_.classes)
    if (c.id >= 0 && c.id < int(kUnknownLabel)) known_[size_t(c.id)] = 1;
}

std::string LabeledFrameSource::description() const {
  return inner_->description() + " + labels " + dir_.folder();
}

RgbdFrame LabeledFrameSource::load(int index) const {
  RgbdFrame frame = inner_->load(index);
  const Intrinsics k = inner_->depthIntrinsics();
  LabelLookup lookup = dir_.load(frame.name, frame.index, k.width, k.height);
  if (!lookup.labels) {
    if (missing_ == MissingLabels::Error)
      throw Error("frame " + frame.name + ": label map " + lookup.path +
                  " not found (pass --labels-missing skip to fuse such frames without labels)");
    std::lock_guard<std::mutex> lock(mutex_);
    missing_by_index_[index] = lookup.path;
    return frame;
  }
  // Ids the class table does not name are not voted: fusing them would put nameless classes
  // into the scene. They are counted so the user can fix the table.
  std::map<int, long long> unknown;
  LabelImage& labels = *lookup.labels;
  for (int i = 0, n = labels.width() * labels.height(); i < n; ++i) {
    uint16_t& l = labels.data()[i];
    if (l != kUnknownLabel && !known_[l]) {
      ++unknown[l];
      l = kUnknownLabel;
    }
  }
  frame.labels = std::move(labels);
  std::lock_guard<std::mutex> lock(mutex_);
  ++stats_.frames_labelled;
  for (const auto& [id, count] : unknown) stats_.unknown_id_pixels[id] += count;
  return frame;
}

LabelStats LabeledFrameSource::stats() const {
  std::lock_guard<std::mutex> lock(mutex_);
  LabelStats out = stats_;
  for (const auto& [index, path] : missing_by_index_) out.missing_files.push_back(path);
  return out;
}

}  // namespace vf
