#include "core/output_lock.h"

#include <fcntl.h>
#include <sys/file.h>
#include <sys/stat.h>
#include <unistd.h>

#include <cerrno>
#include <chrono>
#include <cstdlib>
#include <cstring>
#include <filesystem>
#include <map>
#include <mutex>
#include <thread>

#include "core/error.h"

namespace vf {
namespace {

namespace fs = std::filesystem;

// The locks this process holds: lock file path -> its descriptor, open (and so locked) until the
// process ends. Never destroyed: the signal thread may use it while static objects are destroyed.
struct HeldLocks {
  std::mutex mutex;
  std::map<std::string, int> fds;
  bool files_removed = false;  // the process is ending; no new lock
};
HeldLocks& held() {
  static HeldLocks* locks = new HeldLocks;
  return *locks;
}

std::string withoutTrailingSlashes(std::string path) {
  while (path.size() > 1 && path.back() == '/') path.pop_back();
  return path;
}

// PID written by the holder; 0 when it cannot be read. The holder writes it just after it takes
// the lock, so an empty file is read again for a moment.
long holderPid(int fd) {
  for (int attempt = 0; attempt < 50; ++attempt) {
    char text[32] = {};
    const ssize_t n = ::pread(fd, text, sizeof text - 1, 0);
    if (n > 0) return std::strtol(text, nullptr, 10);
    std::this_thread::sleep_for(std::chrono::milliseconds(2));
  }
  return 0;
}

// Whether `fd` is still the file at `path` (a finishing holder removes the path, then unlocks).
bool stillNamedBy(int fd, const std::string& path) {
  struct stat by_fd {}, by_path {};
  return ::fstat(fd, &by_fd) == 0 && ::stat(path.c_str(), &by_path) == 0 && by_fd.st_dev == by_path.st_dev &&
         by_fd.st_ino == by_path.st_ino;
}

// Opens and locks `lock`; -1 when the file was replaced meanwhile (try again). Throws when another
// process holds it or it cannot be created.
int tryLock(const std::string& lock, const std::string& target) {
  const int fd = ::open(lock.c_str(), O_RDWR | O_CREAT | O_CLOEXEC, 0644);
  if (fd < 0)
    throw Error("cannot write " + target + ": cannot create its lock file " + lock + " (" + std::strerror(errno) + ")");
  if (::flock(fd, LOCK_EX | LOCK_NB) != 0) {
    const int err = errno;
    const long pid = err == EWOULDBLOCK ? holderPid(fd) : 0;
    ::close(fd);
    if (err != EWOULDBLOCK)
      throw Error("cannot write " + target + ": cannot lock " + lock + " (" + std::strerror(err) + ")");
    throw Error(target + " is being written by another vdbfuse run (" +
                (pid > 0 ? "PID " + std::to_string(pid) : "its PID is in " + lock) +
                "); wait for it to end, or write to another path");
  }
  if (!stillNamedBy(fd, lock)) {
    ::close(fd);
    return -1;
  }
  const std::string pid = std::to_string(::getpid()) + "\n";
  if (::ftruncate(fd, 0) != 0 || ::pwrite(fd, pid.data(), pid.size(), 0) != ssize_t(pid.size())) {
    const int err = errno;
    ::unlink(lock.c_str());
    ::close(fd);
    throw Error("cannot write " + target + ": cannot write its lock file " + lock + " (" + std::strerror(err) +
                "; disk full?)");
  }
  return fd;
}

}  // namespace

std::string outputLockPath(const std::string& target) {
  const fs::path t = fs::absolute(fs::path(withoutTrailingSlashes(target))).lexically_normal();
  std::error_code ec;
  // The folder resolved (two spellings of it share one lock), the name not: a link named as the
  // output is what the output replaces.
  fs::path folder = fs::weakly_canonical(t.parent_path(), ec);
  if (ec) folder = t.parent_path();
  return (folder / ("." + t.filename().string() + ".lock")).string();
}

void lockOutputForThisRun(const std::string& target) {
  const std::string lock = outputLockPath(target);
  HeldLocks& locks = held();
  std::lock_guard<std::mutex> guard(locks.mutex);
  if (locks.fds.count(lock)) return;
  if (locks.files_removed) throw Error("cannot write " + target + ": the run is ending");
  for (int attempt = 0; attempt < 100; ++attempt) {
    const int fd = tryLock(lock, target);
    if (fd < 0) continue;
    if (locks.fds.empty()) std::atexit(removeOutputLockFiles);
    locks.fds[lock] = fd;
    return;
  }
  throw Error("cannot write " + target + ": its lock file " + lock + " keeps being replaced");
}

bool holdsOutputLock(const std::string& target) {
  HeldLocks& locks = held();
  std::lock_guard<std::mutex> guard(locks.mutex);
  return locks.fds.count(outputLockPath(target)) > 0;
}

void removeOutputLockFiles() {
  HeldLocks& locks = held();
  std::lock_guard<std::mutex> guard(locks.mutex);
  if (!locks.files_removed)
    for (const auto& [path, fd] : locks.fds) ::unlink(path.c_str());  // still locked: see the header
  locks.files_removed = true;
}

}  // namespace vf
