#include "io/labeled_source.h"

#include <algorithm>
#include <sstream>

#include "core/error.h"

namespace vf {

MissingLabels parseMissingLabels(const std::string& text) {
  if (text == "skip") return MissingLabels::Skip;
  if (text == "error") return MissingLabels::Error;
  throw Error("--labels-missing " + text + ": expected skip or error");
}

namespace {

std::string validNames(const ClassTable& table) {
  std::string names;
  for (const ClassInfo& c : table.classes) {
    if (!names.empty()) names += ", ";
    names += c.name + " (" + std::to_string(c.id) + ")";
  }
  return names.empty() ? "none: the class table is empty" : names;
}

bool parseId(const std::string& s, int& id) {
  if (s.empty() || s.size() > 6 || !std::all_of(s.begin(), s.end(), [](char c) { return c >= '0' && c <= '9'; }))
    return false;
  id = std::stoi(s);
  return true;
}

}  // namespace

std::vector<int> resolveClassList(const ClassTable& table, const std::string& list, const std::string& option) {
  std::vector<int> ids;
  std::stringstream ss(list);
  std::string item;
  while (std::getline(ss, item, ',')) {
    item.erase(0, item.find_first_not_of(" \t"));
    item.erase(item.find_last_not_of(" \t") + 1);
    if (item.empty()) continue;
    int id = -1;
    const ClassInfo* c = table.findName(item);
    if (!c && parseId(item, id)) c = table.findId(id);
    if (!c) throw Error(option + " " + list + ": unknown class '" + item + "'; valid: " + validNames(table));
    if (std::find(ids.begin(), ids.end(), c->id) == ids.end()) ids.push_back(c->id);
  }
  if (ids.empty()) throw Error(option + " '" + list + "': no class given; valid: " + validNames(table));
  return ids;
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
