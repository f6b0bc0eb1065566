#include "core/atomic_output.h"

#include <fcntl.h>
#include <unistd.h>

#include <atomic>
#include <cerrno>
#include <cstring>
#include <filesystem>
#include <map>
#include <mutex>
#include <set>
#include <vector>

#include "core/error.h"

namespace vf {
namespace {

namespace fs = std::filesystem;

// Temporaries not yet committed or removed, for removeAllPendingOutputs().
std::mutex g_pending_mutex;
std::set<std::string>& pending() {
  static std::set<std::string> paths;
  return paths;
}
void track(const std::string& path) {
  std::lock_guard<std::mutex> lock(g_pending_mutex);
  pending().insert(path);
}
// Old outputs moved aside while a folder commit swaps the new one in: aside -> target. Until the
// swap is done they are the user's data, to be put back, never removed, if the process must end.
std::map<std::string, std::string>& asides() {
  static std::map<std::string, std::string> paths;
  return paths;
}
void untrack(const std::string& path) {
  std::lock_guard<std::mutex> lock(g_pending_mutex);
  pending().erase(path);
  asides().erase(path);
}
void trackAside(const std::string& aside, const std::string& target) {
  std::lock_guard<std::mutex> lock(g_pending_mutex);
  asides()[aside] = target;
}
void removeTracked(const std::string& path) {
  std::error_code ec;
  fs::remove_all(path, ec);
  untrack(path);
}

fs::path folderOf(const fs::path& target) {
  return target.has_parent_path() ? target.parent_path() : fs::path(".");
}

std::string temporaryFor(const std::string& target) {
  static std::atomic<unsigned> counter{0};
  const fs::path t(target);
  if (t.filename().empty()) throw Error("cannot write '" + target + "': not a file name");
  if (!fs::is_directory(folderOf(t)))
    throw Error("cannot write " + target + ": folder " + folderOf(t).string() + " does not exist");
  // The target's extension ends the name too: writers that pick a format from it (OpenCV's
  // video writer) see the same one.
  return (folderOf(t) / fs::path(temporaryPrefix(target) + std::to_string(::getpid()) + "_" +
                                 std::to_string(counter++) + t.extension().string()))
      .string();
}

std::string errnoText() { return std::strerror(errno); }

bool syncPath(const std::string& path, int flags) {
  const int fd = ::open(path.c_str(), flags | O_CLOEXEC);
  if (fd < 0) return false;
  const bool ok = ::fsync(fd) == 0 || errno == EINVAL;  // EINVAL: this file system cannot sync
  return ::close(fd) == 0 && ok;
}

// The one rename of the project: everything that appears under its final name comes through here.
bool tryRename(const std::string& from, const std::string& to) { return ::rename(from.c_str(), to.c_str()) == 0; }

void renameInto(const std::string& from, const std::string& to, const std::string& target) {
  if (!tryRename(from, to))
    throw Error("cannot write " + target + ": cannot move the finished output into place (" + errnoText() + ")");
}

}  // namespace

std::string temporaryPrefix(const std::string& target) {
  return "." + fs::path(target).filename().string() + ".tmp";
}

int removeStaleTemporaries(const std::string& target) {
  const fs::path t(target);
  const std::string prefix = temporaryPrefix(target);
  std::error_code ec;
  int removed = 0;
  for (const auto& entry : fs::directory_iterator(folderOf(t), ec)) {
    if (entry.path().filename().string().rfind(prefix, 0) != 0) continue;
    fs::remove_all(entry.path(), ec);
    ++removed;
  }
  return removed;
}

void removeAllPendingOutputs() {
  std::lock_guard<std::mutex> lock(g_pending_mutex);
  std::error_code ec;
  // Another thread may still be adding files to a temporary folder: removal fails on the newcomers
  // (the folder is not empty), so it is repeated until the folder is gone, after which no file can
  // be created in it any more.
  for (const std::string& path : pending())
    for (int attempt = 0; attempt < 1000 && fs::exists(fs::symlink_status(path, ec)); ++attempt) fs::remove_all(path, ec);
  pending().clear();
  for (const auto& [aside, target] : asides()) {
    if (!fs::exists(fs::symlink_status(target, ec))) tryRename(aside, target);  // the swap had not happened
    else fs::remove_all(aside, ec);
  }
  asides().clear();
}

AtomicFile::AtomicFile(std::string target) : target_(std::move(target)), temp_(temporaryFor(target_)) {
  track(temp_);
}

AtomicFile::~AtomicFile() {
  if (file_) std::fclose(file_);
  if (!committed_) removeTracked(temp_);
}

void AtomicFile::fail(const std::string& why) {
  if (file_) std::fclose(file_);
  file_ = nullptr;
  removeTracked(temp_);
  committed_ = true;  // nothing left to clean up
  throw Error("cannot write " + target_ + ": " + why);
}

void AtomicFile::write(const void* data, size_t bytes) {
  if (committed_) throw Error("cannot write " + target_ + ": written to after commit");
  if (!file_) {
    file_ = std::fopen(temp_.c_str(), "wb");
    if (!file_) fail("cannot create " + temp_ + " (" + errnoText() + ")");
  }
  if (bytes > 0 && std::fwrite(data, 1, bytes, file_) != bytes)
    fail("write failed (" + errnoText() + "; disk full?)");
}

void AtomicFile::commit() {
  if (committed_) throw Error("cannot write " + target_ + ": committed twice");
  if (file_) {
    const bool flushed = std::fflush(file_) == 0 && (::fsync(::fileno(file_)) == 0 || errno == EINVAL);
    const std::string why = flushed ? "" : errnoText();
    const bool closed = std::fclose(file_) == 0;
    file_ = nullptr;
    if (!flushed || !closed) fail("write failed (" + (why.empty() ? errnoText() : why) + "; disk full?)");
  } else if (!fs::exists(temp_)) {
    write(nullptr, 0);  // nothing was written: an empty file is the output
    return commit();
  } else if (!syncPath(temp_, O_RDONLY)) {
    fail("cannot sync " + temp_ + " (" + errnoText() + ")");
  }
  std::error_code ec;
  if (fs::is_directory(target_, ec)) fail("a folder of that name exists");
  try {
    renameInto(temp_, target_, target_);
  } catch (const Error&) {
    removeTracked(temp_);
    committed_ = true;
    throw;
  }
  untrack(temp_);
  committed_ = true;
  syncPath(folderOf(fs::path(target_)).string(), O_RDONLY | O_DIRECTORY);
}

AtomicFolder::AtomicFolder(std::string target) : target_(std::move(target)) {
  while (!target_.empty() && target_.size() > 1 && target_.back() == '/') target_.pop_back();
  temp_ = temporaryFor(target_);
  track(temp_);
  std::error_code ec;
  if (!fs::create_directory(temp_, ec) || ec) {
    untrack(temp_);
    throw Error("cannot write " + target_ + ": cannot create " + temp_ + " (" + ec.message() + ")");
  }
}

AtomicFolder::~AtomicFolder() {
  if (!committed_) removeTracked(temp_);
}

std::string AtomicFolder::file(const std::string& name) const { return (fs::path(temp_) / name).string(); }

void AtomicFolder::commit() {
  if (committed_) throw Error("cannot write " + target_ + ": committed twice");
  std::error_code ec;
  for (const auto& entry : fs::recursive_directory_iterator(temp_, ec))
    if (entry.is_regular_file() && !syncPath(entry.path().string(), O_RDONLY))
      throw Error("cannot write " + target_ + ": cannot sync " + entry.path().string() + " (" + errnoText() + ")");
  if (ec) throw Error("cannot write " + target_ + ": cannot list " + temp_ + " (" + ec.message() + ")");
  // A folder cannot be renamed over a non-empty one: the old one steps aside first and goes once
  // the new one is in place (or comes back if that fails).
  std::string old;
  if (fs::exists(target_, ec)) {
    if (!fs::is_directory(target_, ec)) throw Error("cannot write " + target_ + ": a file of that name exists");
    old = temporaryFor(target_);
    trackAside(old, target_);
    renameInto(target_, old, target_);
  }
  try {
    renameInto(temp_, target_, target_);
  } catch (const Error&) {
    if (!old.empty() && tryRename(old, target_)) untrack(old);
    throw;
  }
  untrack(temp_);
  committed_ = true;
  if (!old.empty()) removeTracked(old);
  syncPath(folderOf(fs::path(target_)).string(), O_RDONLY | O_DIRECTORY);
}

void AtomicFolder::commitFilesInto(const std::string& folder) {
  if (committed_) throw Error("cannot write " + target_ + ": committed twice");
  std::error_code ec;
  std::vector<fs::path> files;
  for (const auto& entry : fs::directory_iterator(temp_, ec)) {
    if (!entry.is_regular_file() || !syncPath(entry.path().string(), O_RDONLY))
      throw Error("cannot write " + (fs::path(folder) / entry.path().filename()).string() + ": cannot sync it (" +
                  errnoText() + ")");
    files.push_back(entry.path());
  }
  if (ec) throw Error("cannot write " + target_ + ": cannot list " + temp_ + " (" + ec.message() + ")");
  for (const fs::path& file : files) {
    const std::string to = (fs::path(folder) / file.filename()).string();
    renameInto(file.string(), to, to);
  }
  committed_ = true;
  removeTracked(temp_);
  syncPath(folder, O_RDONLY | O_DIRECTORY);
}

void writeFileAtomic(const std::string& path, const std::string& bytes) {
  AtomicFile file(path);
  file.write(bytes);
  file.commit();
}

}  // namespace vf
