#pragma once
// Outputs that appear whole or not at all: every file and folder vdbfuse writes goes through here.
//
// A writer fills a temporary sibling of the target (".<name>.tmp<pid>_<n><ext>", same folder, so the
// rename stays on one file system), then commit() checks that every write succeeded, syncs the
// data to disk, renames the temporary onto the target and syncs the folder. On any failure, on
// destruction without commit(), and on SIGINT/SIGTERM (removeAllPendingOutputs(), called by the
// app's signal thread) the temporary is removed and the old target is left as it was. That cleanup
// and a commit never interleave: the cleanup waits for a commit's renames to end, and no commit
// (nor a new temporary) starts after it, so the target always holds the old output or the whole
// new one.
#include <cstddef>
#include <cstdio>
#include <string>

namespace vf {

class AtomicFile {
 public:
  // Throws vf::Error naming `target` when its folder does not exist.
  explicit AtomicFile(std::string target);
  ~AtomicFile();
  AtomicFile(const AtomicFile&) = delete;
  AtomicFile& operator=(const AtomicFile&) = delete;

  const std::string& target() const { return target_; }
  // For libraries that write to a path themselves (OpenVDB, OpenCV's video writer): they write
  // here, and the caller verifies the content before commit() (their streams report no errors).
  const std::string& tempPath() const { return temp_; }

  // Appends to the temporary; a failed write throws vf::Error naming the target (disk full...).
  void write(const void* data, size_t bytes);
  void write(const std::string& bytes) { write(bytes.data(), bytes.size()); }

  // Syncs, renames onto the target, syncs the folder. Throws vf::Error naming the target.
  void commit();

 private:
  void fail(const std::string& why);
  std::string target_, temp_;
  std::FILE* file_ = nullptr;
  bool committed_ = false;
};

// A folder of outputs (a converted dataset, a Blender export) written into a temporary folder
// and renamed into place by commit(). An existing target folder is replaced only by commit(),
// which the caller reaches after its own overwrite policy (--force) allowed it: the two are
// exchanged in one step (renameat2 RENAME_EXCHANGE), so that the target's name holds the old
// folder or the new one at every instant, and the old one is then removed. Where the file system
// cannot exchange, the old folder steps aside for the new one.
class AtomicFolder {
 public:
  explicit AtomicFolder(std::string target);  // creates the temporary folder
  ~AtomicFolder();
  AtomicFolder(const AtomicFolder&) = delete;
  AtomicFolder& operator=(const AtomicFolder&) = delete;

  const std::string& target() const { return target_; }
  const std::string& tempPath() const { return temp_; }
  // Path of `name` inside the temporary folder, for writers that commit files there.
  std::string file(const std::string& name) const;

  void commit();
  // For a set of files that sit beside other files (per-class meshes): once all are written into
  // the temporary folder, renames each into the existing `folder` (replacing a file of its name)
  // and removes the temporary. A write that failed before left none of them in place.
  void commitFilesInto(const std::string& folder);

 private:
  std::string target_, temp_;
  bool committed_ = false;
};

// One call for a file whose bytes are in memory.
void writeFileAtomic(const std::string& path, const std::string& bytes);

// Removes every temporary not yet committed or removed, and this process's output lock files
// (core/output_lock.h). For the app's signal thread, which calls it from normal (not
// signal-handler) context before the process ends: it waits for a commit in progress, and from
// then on every new temporary and every commit throws vf::Error (the process is ending).
void removeAllPendingOutputs();

// The prefix every temporary of `target` starts with, so that a later run can find the ones a
// killed process (SIGKILL) left behind.
std::string temporaryPrefix(const std::string& target);
// Removes those leftovers beside `target` (".<name>.tmp<pid>_<n><ext>", none of this process);
// returns how many there were. Only under the target's lock (lockOutputForThisRun()): then no
// other run is writing them; throws vf::Error without it.
int removeStaleTemporaries(const std::string& target);

}  // namespace vf
