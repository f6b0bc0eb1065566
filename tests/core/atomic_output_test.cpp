// Outputs appear whole or not at all (core/atomic_output.h): a failed write, an abandoned one and
// a full disk all leave the old target as it was and no temporary behind.
#include <gtest/gtest.h>
#include <signal.h>
#include <sys/resource.h>
#include <sys/stat.h>
#include <sys/wait.h>
#include <unistd.h>

#include <filesystem>
#include <fstream>
#include <sstream>

#include "core/atomic_output.h"
#include "core/byte_reader.h"
#include "core/error.h"
#include "core/mapped_file.h"
#include "core/output_lock.h"
#include "test_data.h"

namespace vf {
namespace {

namespace fs = std::filesystem;

std::string slurp(const std::string& path) {
  std::ifstream in(path, std::ios::binary);
  std::ostringstream s;
  s << in.rdbuf();
  return s.str();
}

size_t entries(const std::string& dir) {
  return size_t(std::distance(fs::directory_iterator(dir), fs::directory_iterator()));
}

// Files larger than `bytes` cannot be written while it lives: write() fails with EFBIG, as on a
// full disk (SIGXFSZ, which would end the process, is ignored meanwhile).
class FileSizeLimit {
 public:
  explicit FileSizeLimit(rlim_t bytes) {
    getrlimit(RLIMIT_FSIZE, &old_);
    previous_ = signal(SIGXFSZ, SIG_IGN);
    rlimit limit = old_;
    limit.rlim_cur = bytes;
    setrlimit(RLIMIT_FSIZE, &limit);
  }
  ~FileSizeLimit() {
    setrlimit(RLIMIT_FSIZE, &old_);
    signal(SIGXFSZ, previous_);
  }

 private:
  rlimit old_{};
  sighandler_t previous_;
};

TEST(AtomicFile, CommitReplacesTheTargetAndLeavesNothingElse) {
  const std::string dir = test::tempDir("atomic_file");
  const std::string target = dir + "/out.txt";
  writeFileAtomic(target, "old");
  writeFileAtomic(target, "new content");
  EXPECT_EQ(slurp(target), "new content");
  EXPECT_EQ(entries(dir), 1u);
}

TEST(AtomicFile, AnAbandonedOrFailedWriteKeepsTheOldTarget) {
  const std::string dir = test::tempDir("atomic_file_fail");
  const std::string target = dir + "/scene.vdb";
  writeFileAtomic(target, "the good scene");
  {
    AtomicFile file(target);
    file.write("half a scene");
    EXPECT_EQ(fs::path(file.tempPath()).extension(), ".vdb");  // writers that go by the extension see it
    EXPECT_EQ(entries(dir), 2u);
  }  // destroyed without commit
  EXPECT_EQ(slurp(target), "the good scene");
  EXPECT_EQ(entries(dir), 1u);

  const std::string big(1 << 20, 'x');
  {
    FileSizeLimit limit(64 * 1024);
    const std::string error = test::errorOf([&] { writeFileAtomic(target, big); });
    EXPECT_NE(error.find("cannot write " + target), std::string::npos) << error;
  }
  EXPECT_EQ(slurp(target), "the good scene");
  EXPECT_EQ(entries(dir), 1u) << "a temporary was left after the failed write";
  EXPECT_NE(test::errorOf([&] { writeFileAtomic(dir + "/missing/x.txt", "x"); }).find("does not exist"),
            std::string::npos);
}

// Runs `body` in a child process (what it does cannot be undone in this one) and returns its exit
// status, or 128 + the signal that ended it.
template <class Body>
int statusOfChild(Body&& body) {
  const pid_t pid = fork();
  if (pid == 0) {
    int status = 99;
    try {
      status = body();
    } catch (...) {
      status = 98;
    }
    _exit(status);
  }
  int raw = 0;
  waitpid(pid, &raw, 0);
  return WIFEXITED(raw) ? WEXITSTATUS(raw) : 128 + WTERMSIG(raw);
}

TEST(AtomicFile, PendingOutputsAreRemovedOnRequestAndNoneMadeAfter) {
  const std::string dir = test::tempDir("atomic_pending");
  // In a child: the cleanup is what the signal thread does before the process ends, for good.
  const int status = statusOfChild([&] {
    AtomicFile a(dir + "/a.ply");
    a.write("partial");
    AtomicFolder b(dir + "/export");
    std::ofstream(b.file("mesh.ply")) << "partial";
    if (entries(dir) != 2) return 1;
    removeAllPendingOutputs();
    if (entries(dir) != 0) return 2;
    // From now on the process is ending: nothing new is started (it would be left behind).
    const std::string error = test::errorOf([&] { writeFileAtomic(dir + "/late.txt", "x"); });
    if (error.find("stopped by a signal") == std::string::npos) return 3;
    if (test::errorOf([&] { a.commit(); }).find("stopped by a signal") == std::string::npos) return 4;
    return entries(dir) == 0 ? 0 : 5;
  });
  EXPECT_EQ(status, 0) << "1, 2: temporaries before/after the cleanup; 3, 4: a write after it; 5: left behind";
}

TEST(AtomicFile, StaleTemporariesAreRemovedOnlyUnderTheLockAndOnlyThose) {
  const std::string dir = test::tempDir("atomic_stale");
  const std::string target = dir + "/a.ply";
  const std::string prefix = dir + "/" + temporaryPrefix(target);
  std::ofstream(prefix + "4242_0.ply") << "left by a SIGKILL";
  std::error_code ec;
  fs::create_directory(prefix + "4243_7.ply", ec);  // a killed folder commit's
  std::ofstream(dir + "/a.ply.txt") << "a user's file";
  std::ofstream(prefix + "_notes.ply") << "a user's file too: not a temporary's name";
  std::ofstream(prefix + "4244_1.ply.bak") << "nor this";
  // Without the lock another run may be writing them.
  EXPECT_NE(test::errorOf([&] { removeStaleTemporaries(target); }).find("under its lock"), std::string::npos);
  EXPECT_EQ(entries(dir), 5u);
  lockOutputForThisRun(target);
  AtomicFile live(target);  // this process's own: never a leftover
  live.write("being written");
  EXPECT_EQ(removeStaleTemporaries(target), 2);
  EXPECT_EQ(entries(dir), 5u);  // three user files, the live temporary, the lock file
  EXPECT_TRUE(fs::exists(live.tempPath()));
  EXPECT_TRUE(fs::exists(outputLockPath(target)));
}

TEST(OutputLock, ASecondProcessIsRefusedWithTheHoldersPidUntilItDies) {
  const std::string dir = test::tempDir("output_lock");
  const std::string target = dir + "/scene.vdb";
  int ready[2];
  ASSERT_EQ(pipe(ready), 0);
  const pid_t holder = fork();
  if (holder == 0) {
    lockOutputForThisRun(target);
    const char byte = 1;
    (void)!::write(ready[1], &byte, 1);
    for (;;) pause();
  }
  char byte = 0;
  ASSERT_EQ(::read(ready[0], &byte, 1), 1);
  EXPECT_FALSE(holdsOutputLock(target));
  // The "second run" is a child too: a refused lock attempt leaves this process free to take it.
  const std::string expected = target + " is being written by another vdbfuse run (PID " + std::to_string(holder) + ")";
  EXPECT_EQ(statusOfChild([&] {
              const std::string error = test::errorOf([&] { lockOutputForThisRun(target); });
              return error.find(expected) != std::string::npos ? 0 : 1;
            }),
            0)
      << expected;
  // kill -9: the kernel releases the lock; the file it leaves blocks nobody.
  kill(holder, SIGKILL);
  waitpid(holder, nullptr, 0);
  EXPECT_TRUE(fs::exists(outputLockPath(target)));
  EXPECT_NO_THROW(lockOutputForThisRun(target));
  EXPECT_TRUE(holdsOutputLock(target));
  // Removed as this run ends, still locked until then.
  EXPECT_EQ(statusOfChild([&] {
              removeOutputLockFiles();
              return fs::exists(outputLockPath(target)) ? 1 : 0;
            }),
            0);
  close(ready[0]);
  close(ready[1]);
}

TEST(AtomicFolder, ReplacesAFolderWholeAndOnlyOnCommit) {
  const std::string dir = test::tempDir("atomic_folder");
  const std::string target = dir + "/export";
  fs::create_directories(target);
  std::ofstream(target + "/old.ply") << "old";
  {
    AtomicFolder out(target);
    std::ofstream(out.file("new.ply")) << "new";
  }  // abandoned
  EXPECT_TRUE(fs::exists(target + "/old.ply"));
  EXPECT_EQ(entries(dir), 1u);
  AtomicFolder out(target);
  writeFileAtomic(out.file("new.ply"), "new");
  out.commit();
  EXPECT_FALSE(fs::exists(target + "/old.ply"));
  EXPECT_EQ(slurp(target + "/new.ply"), "new");
  EXPECT_EQ(entries(dir), 1u);
}

TEST(MappedFile, RefusesWhatIsNotARegularFileWithoutBlocking) {
  const std::string dir = test::tempDir("mapped_file");
  const std::string fifo = dir + "/pipe";
  ASSERT_EQ(mkfifo(fifo.c_str(), 0600), 0);
  EXPECT_NE(test::errorOf([&] { MappedFile f(fifo, "scene file"); }).find("not a regular file"), std::string::npos);
  EXPECT_NE(test::errorOf([&] { MappedFile f(dir, "scene file"); }).find("not a regular file"), std::string::npos);
  EXPECT_NE(test::errorOf([&] { MappedFile f(dir + "/none", "checkpoint"); }).find("checkpoint does not exist"),
            std::string::npos);
  writeFileAtomic(dir + "/four", std::string("\x01\x00\x00\x00", 4));
  const MappedFile f(dir + "/four", "file");
  ByteReader r(f.data(), f.size(), dir + "/four: damaged");
  EXPECT_EQ(r.read<uint32_t>("count"), 1u);
  const std::string error = test::errorOf([&] { r.read<uint32_t>("next count"); });
  EXPECT_NE(error.find("four: damaged (byte 4): next count needs 4 bytes, 0 are left"), std::string::npos) << error;
}

}  // namespace
}  // namespace vf
