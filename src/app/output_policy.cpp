#include "app/output_policy.h"

#include <algorithm>
#include <cctype>

#include "core/atomic_output.h"
#include "core/error.h"
#include "core/output_lock.h"

namespace vf::app {
namespace fs = std::filesystem;
namespace {

// The path as the file system resolves it, for comparisons (symbolic links, "..", "./").
fs::path resolved(const std::string& path) {
  std::error_code ec;
  const fs::path p = fs::weakly_canonical(fs::absolute(path, ec), ec);
  return ec ? fs::path(path).lexically_normal() : p;
}

bool isWithin(const fs::path& inner, const fs::path& folder) {
  const auto [end, unused] = std::mismatch(folder.begin(), folder.end(), inner.begin(), inner.end());
  return end == folder.end();
}

}  // namespace

void OutputPolicy::requireExtension(const std::string& path, const std::vector<std::string>& extensions,
                                    const std::string& option) {
  std::string ext = fs::path(path).extension().string();
  std::transform(ext.begin(), ext.end(), ext.begin(), [](unsigned char c) { return char(std::tolower(c)); });
  std::string known;
  for (const std::string& e : extensions) {
    if (ext == e) return;
    known += (known.empty() ? "" : " or ") + e;
  }
  throw Error(option + " " + path + ": this output is written as " + known + "; name it so");
}

void OutputPolicy::input(const std::string& path) { inputs_.push_back({resolved(path), path}); }

void OutputPolicy::file(const std::string& path, const std::string& option) { claim(path, option, false); }

void OutputPolicy::folder(const std::string& path, const std::string& option) { claim(path, option, true); }

void OutputPolicy::filesInto(const std::string& path, const std::string& option) {
  if (path.empty()) throw Error(option + ": the output folder is empty");
  refuseInsideInputs(path, resolved(path), option);
}

void OutputPolicy::refuseInsideInputs(const std::string& path, const fs::path& target, const std::string& option) const {
  std::error_code ec;
  for (const Input& in : inputs_) {
    // A file written into an input folder changes the input: frames a dataset reader lists by
    // name, a capture's rgbd/ folder, a dataset's groundtruth.txt (issue 35).
    if (in.resolved != target && isWithin(target, in.resolved) && fs::is_directory(in.resolved, ec))
      throw Error(option + " " + path + " is inside " + in.given + ", a folder this command reads; writing there " +
                  "would change its input. Write the output elsewhere");
  }
}

void OutputPolicy::claim(const std::string& path, const std::string& option, bool is_folder) {
  if (path.empty()) throw Error(option + ": the output path is empty");
  const fs::path target = resolved(path);
  for (const Input& in : inputs_)
    if (in.resolved == target || (is_folder && isWithin(in.resolved, target)))
      throw Error(option + " " + path + (in.resolved == target ? " is" : " holds") + " an input of this command (" +
                  in.given + "); write the output elsewhere");
  refuseInsideInputs(path, target, option);
  for (const auto& [out, other] : outputs_)
    if (out == target) throw Error(option + " " + path + " is also the output of " + other + "; give each its own path");
  const fs::path parent = fs::path(path).has_parent_path() ? fs::path(path).parent_path() : fs::path(".");
  std::error_code ec;
  if (!fs::is_directory(parent, ec))
    throw Error(option + " " + path + ": folder " + parent.string() + " does not exist");
  const bool exists = fs::exists(fs::symlink_status(path, ec));
  if (exists && !force_)
    throw Error(option + " " + path + " already exists; pass --force to " +
                (is_folder ? "replace it with everything in it" : "overwrite it"));
  if (exists && is_folder != fs::is_directory(path, ec))
    throw Error(option + " " + path + " exists and is " + (is_folder ? "not a folder" : "a folder"));
  // Held until the process ends; then no other run writes this output, and the temporaries beside
  // it are a killed run's leftovers (issue 35: two runs on one -o both "succeeded").
  lockOutputForThisRun(path);
  removeStaleTemporaries(path);
  outputs_.emplace_back(target, option);
}

}  // namespace vf::app
