#include "core/atomic_output.h"

#include <fcntl.h>
#include <stdio.h>  // renameat2
#include <unistd.h>

#include <algorithm>
#include <atomic>
#include <cerrno>
#include <cstring>
#include <filesystem>
#include <mutex>
#include <set>
#include <vector>

#include "core/error.h"
#include "core/output_lock.h"

namespace vf {
namespace {

namespace fs = std::filesystem;

// Temporaries not yet committed or removed, and the lock that orders every change of them against
// the signal thread's cleanup (removeAllPendingOutputs()).
//
// Why every create and every commit holds the lock: the signal thread removes the temporaries and
// then ends the process while the command's threads go on running. A folder commit that
// interleaved with it lost the user's folder (issue 35): the cleanup removed the new temporary,
// the commit then moved the old folder aside, and the process died before it could move it back;
// the old content sat in a temporary that the next run's sweep deleted. A cleanup that ran during
// the commit's rename could also remove half of the new folder after it had taken the target's
// name. So the cleanup takes the same lock: it waits for a commit in progress (a few renames), and
// it closes the registry as it runs: a later create or commit throws (the process is about to end
// by the signal) instead of starting a change that the end of the process would cut in half.
// Never destroyed: the signal thread may use it while static objects are being destroyed.
struct Registry {
  std::mutex mutex;
  std::set<std::string> pending;
  bool closed = false;  // removeAllPendingOutputs() has run: the process is ending
};
Registry& registry() {
  static Registry* r = new Registry;
  return *r;
}

// Runs `change(pending)` under the lock unless the cleanup has run; then throws, naming `target`.
template <class Change>
auto whileOpen(const std::string& target, Change&& change) {
  Registry& r = registry();
  std::lock_guard<std::mutex> lock(r.mutex);
  if (r.closed) throw Error("cannot write " + target + ": stopped by a signal, the output is left as it was");
  return change(r.pending);
}

void untrack(const std::string& path) {
  std::lock_guard<std::mutex> lock(registry().mutex);
  registry().pending.erase(path);
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
std::string errnoText(int err) { return std::strerror(err); }

bool syncPath(const std::string& path, int flags) {
  const int fd = ::open(path.c_str(), flags | O_CLOEXEC);
  if (fd < 0) return false;
  const bool ok = ::fsync(fd) == 0 || errno == EINVAL;  // EINVAL: this file system cannot sync
  return ::close(fd) == 0 && ok;
}

// The renames of the project: everything that appears under its final name comes through here.
bool tryRename(const std::string& from, const std::string& to) { return ::rename(from.c_str(), to.c_str()) == 0; }

// Swaps two existing paths in one step (Linux renameat2 RENAME_EXCHANGE): the target names the old
// folder, then the new one, never nothing, even if the process is killed (-9) in between. False
// with errno EINVAL or ENOSYS where the file system or the kernel cannot.
bool tryExchange(const std::string& a, const std::string& b) {
#ifdef RENAME_EXCHANGE
  return ::renameat2(AT_FDCWD, a.c_str(), AT_FDCWD, b.c_str(), RENAME_EXCHANGE) == 0;
#else
  errno = ENOSYS;
  return false;
#endif
}

void renameInto(const std::string& from, const std::string& to, const std::string& target) {
  if (!tryRename(from, to))
    throw Error("cannot write " + target + ": cannot move the finished output into place (" + errnoText() + ")");
}

// Whether `name` is "<prefix><digits>_<digits><ext>", a temporary as temporaryFor() names them;
// sets `pid` to the first number.
bool isTemporaryName(const std::string& name, const std::string& prefix, const std::string& ext, long& pid) {
  if (name.size() <= prefix.size() + ext.size() || name.compare(0, prefix.size(), prefix) != 0 ||
      name.compare(name.size() - ext.size(), ext.size(), ext) != 0)
    return false;
  const std::string middle = name.substr(prefix.size(), name.size() - prefix.size() - ext.size());
  const size_t underscore = middle.find('_');
  const auto digits = [](const std::string& s) {
    return !s.empty() && s.size() < 19 && std::all_of(s.begin(), s.end(), [](char c) { return c >= '0' && c <= '9'; });
  };
  if (underscore == std::string::npos || !digits(middle.substr(0, underscore)) || !digits(middle.substr(underscore + 1)))
    return false;
  pid = std::stol(middle.substr(0, underscore));
  return true;
}

}  // namespace

std::string temporaryPrefix(const std::string& target) {
  return "." + fs::path(target).filename().string() + ".tmp";
}

int removeStaleTemporaries(const std::string& target) {
  // Only under the output's lock: then no other run is writing this target, and a temporary of
  // it is a leftover of a run that died (kill -9), never a live run's work (issue 35).
  if (!holdsOutputLock(target))
    throw Error("cannot write " + target + ": its leftover temporaries may only be removed under its lock");
  const fs::path t(target);
  const std::string prefix = temporaryPrefix(target), ext = t.extension().string();
  std::error_code ec;
  int removed = 0;
  for (const auto& entry : fs::directory_iterator(folderOf(t), ec)) {
    long pid = 0;
    if (!isTemporaryName(entry.path().filename().string(), prefix, ext, pid) || pid == long(::getpid())) continue;
    fs::remove_all(entry.path(), ec);
    ++removed;
  }
  return removed;
}

void removeAllPendingOutputs() {
  {
    Registry& r = registry();
    std::lock_guard<std::mutex> lock(r.mutex);  // waits for a commit in progress (see Registry)
    r.closed = true;
    std::error_code ec;
    // Another thread may still be adding files to a temporary folder: removal fails on the
    // newcomers (the folder is not empty), so it is repeated until the folder is gone, after which
    // no file can be created in it any more.
    for (const std::string& path : r.pending)
      for (int attempt = 0; attempt < 1000 && fs::exists(fs::symlink_status(path, ec)); ++attempt)
        fs::remove_all(path, ec);
    r.pending.clear();
  }
  removeOutputLockFiles();
}

AtomicFile::AtomicFile(std::string target) : target_(std::move(target)), temp_(temporaryFor(target_)) {
  whileOpen(target_, [&](std::set<std::string>& pending) { pending.insert(temp_); });
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
    // Created under the registry's lock: a file created after the signal thread's cleanup would
    // be left behind.
    int err = 0;
    whileOpen(target_, [&](std::set<std::string>&) {
      file_ = std::fopen(temp_.c_str(), "wb");
      err = errno;
    });
    if (!file_) fail("cannot create " + temp_ + " (" + errnoText(err) + ")");
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
  int err = 0;
  const bool moved = whileOpen(target_, [&](std::set<std::string>& pending) {
    const bool renamed = tryRename(temp_, target_);
    if (renamed) pending.erase(temp_);
    else err = errno;
    return renamed;
  });
  committed_ = true;
  if (!moved) {
    removeTracked(temp_);
    throw Error("cannot write " + target_ + ": cannot move the finished output into place (" + errnoText(err) + ")");
  }
  syncPath(folderOf(fs::path(target_)).string(), O_RDONLY | O_DIRECTORY);
}

AtomicFolder::AtomicFolder(std::string target) : target_(std::move(target)) {
  while (!target_.empty() && target_.size() > 1 && target_.back() == '/') target_.pop_back();
  temp_ = temporaryFor(target_);
  std::error_code ec;
  // Created under the registry's lock, as AtomicFile::write's file.
  const bool created = whileOpen(target_, [&](std::set<std::string>& pending) {
    if (!fs::create_directory(temp_, ec) || ec) return false;
    pending.insert(temp_);
    return true;
  });
  if (!created) throw Error("cannot write " + target_ + ": cannot create " + temp_ + " (" + ec.message() + ")");
}

AtomicFolder::~AtomicFolder() {
  if (!committed_) removeTracked(temp_);
}

std::string AtomicFolder::file(const std::string& name) const { return (fs::path(temp_) / name).string(); }

namespace {

// A folder commit's renames, under the registry's lock. Returns the path that now holds the old
// folder, to be removed ("" when there was none).
std::string swapIntoPlace(const std::string& temp, const std::string& target, std::set<std::string>& pending) {
  std::error_code ec;
  if (!fs::exists(fs::symlink_status(target, ec))) {
    renameInto(temp, target, target);
    pending.erase(temp);
    return "";
  }
  if (!fs::is_directory(target, ec)) throw Error("cannot write " + target + ": a file of that name exists");
  // Exchanged, the temporary holds the old folder: it stays pending, removed by commit() or, if
  // the process must end first, by the cleanup.
  if (tryExchange(temp, target)) return temp;
  if (errno != EINVAL && errno != ENOSYS)
    throw Error("cannot write " + target + ": cannot move the finished output into place (" + errnoText() + ")");
  // No exchange here: a folder cannot be renamed over a non-empty one, so the old one steps aside
  // first and comes back if the new one cannot take its place. The signal's cleanup cannot come in
  // between (the registry's lock); only a kill -9 between the two renames would leave the old
  // folder in the aside temporary instead of under its name.
  const std::string aside = temporaryFor(target);
  renameInto(target, aside, target);
  if (!tryRename(temp, target)) {
    const int err = errno;
    tryRename(aside, target);
    throw Error("cannot write " + target + ": cannot move the finished output into place (" + errnoText(err) + ")");
  }
  pending.erase(temp);
  pending.insert(aside);
  return aside;
}

}  // namespace

void AtomicFolder::commit() {
  if (committed_) throw Error("cannot write " + target_ + ": committed twice");
  std::error_code ec;
  for (const auto& entry : fs::recursive_directory_iterator(temp_, ec))
    if (entry.is_regular_file() && !syncPath(entry.path().string(), O_RDONLY))
      throw Error("cannot write " + target_ + ": cannot sync " + entry.path().string() + " (" + errnoText() + ")");
  if (ec) throw Error("cannot write " + target_ + ": cannot list " + temp_ + " (" + ec.message() + ")");
  const std::string old =
      whileOpen(target_, [&](std::set<std::string>& pending) { return swapIntoPlace(temp_, target_, pending); });
  committed_ = true;
  if (!old.empty()) removeTracked(old);  // may take a while: outside the lock
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
  // All under the registry's lock: a signal's cleanup cannot leave some of the set moved and the
  // others removed.
  whileOpen(target_, [&](std::set<std::string>&) {
    for (const fs::path& file : files) {
      const std::string to = (fs::path(folder) / file.filename()).string();
      renameInto(file.string(), to, to);
    }
  });
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
