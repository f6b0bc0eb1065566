// A signal's cleanup (removeAllPendingOutputs(), what the app's signal thread runs before the
// process ends) that arrives during a folder commit never loses the old folder nor the new one
// (issue 35, cause 1: `convert ... --force` over an old folder lost it about once in 100 signals).
//
// The race is made deterministic: this test binary puts its own rename() and renameat2() in front
// of the C library's (the executable's definitions win), and the chosen rename of a commit first
// starts the cleanup on another thread, gives it every chance to run before the rename, then
// renames; if the cleanup ran meanwhile, the process ends right there, as the signal would end it.
// Each trial runs in a child process (the cleanup is for good), and the parent checks the folder.
#include <dlfcn.h>
#include <gtest/gtest.h>
#include <stdio.h>
#include <sys/wait.h>
#include <unistd.h>

#include <atomic>
#include <chrono>
#include <filesystem>
#include <fstream>
#include <sstream>
#include <thread>

#include "core/atomic_output.h"
#include "core/error.h"
#include "test_data.h"

namespace {

constexpr int kEndedBySignal = 42;  // the child's status when its "signal" ended it
std::atomic<int> g_exit_status{kEndedBySignal};
std::atomic<int> g_trigger_call{0};  // which rename of the commit brings the signal; 0: none
std::atomic<int> g_calls{0};
std::atomic<bool> g_no_exchange{false};  // as on a file system without RENAME_EXCHANGE
std::atomic<bool> g_signalled{false}, g_cleaned{false}, g_may_end{false};

// The signal thread: cleanup, then the end of the process (once the main thread is parked, so
// that the test sees where the commit stood when the process ended).
void endBySignal() {
  vf::removeAllPendingOutputs();
  g_cleaned = true;
  for (int i = 0; i < 5000 && !g_may_end; ++i) std::this_thread::sleep_for(std::chrono::milliseconds(2));
  _exit(g_exit_status);
}

void signalNow() {
  g_signalled = true;
  std::thread(endBySignal).detach();
}

template <class Rename>
int hooked(Rename rename) {
  if (g_trigger_call == 0 || ++g_calls != g_trigger_call) return rename();
  signalNow();
  // 0.5 s for the cleanup to finish first; it cannot while the commit holds it off.
  for (int i = 0; i < 250 && !g_cleaned; ++i) std::this_thread::sleep_for(std::chrono::milliseconds(2));
  const int result = rename();
  if (g_cleaned) {  // the process ends here, right after this rename
    g_may_end = true;
    for (;;) pause();
  }
  return result;
}

}  // namespace

extern "C" int rename(const char* from, const char* to) noexcept {
  static const auto real = reinterpret_cast<int (*)(const char*, const char*)>(dlsym(RTLD_NEXT, "rename"));
  return hooked([&] { return real(from, to); });
}

extern "C" int renameat2(int from_dir, const char* from, int to_dir, const char* to, unsigned flags) noexcept {
  static const auto real =
      reinterpret_cast<int (*)(int, const char*, int, const char*, unsigned)>(dlsym(RTLD_NEXT, "renameat2"));
  if (g_no_exchange && (flags & RENAME_EXCHANGE)) {
    errno = EINVAL;
    return -1;
  }
  return hooked([&] { return real(from_dir, from, to_dir, to, flags); });
}

namespace vf {
namespace {

namespace fs = std::filesystem;

std::string slurp(const std::string& path) {
  std::ifstream in(path, std::ios::binary);
  std::ostringstream s;
  s << in.rdbuf();
  return s.str();
}

// What `dir` holds, one "path=content" line per file and "path/" per folder.
std::string listing(const std::string& dir) {
  std::vector<std::string> lines;
  std::error_code ec;
  for (const auto& e : fs::recursive_directory_iterator(dir, ec)) {
    const std::string rel = fs::relative(e.path(), dir).string();
    lines.push_back(e.is_directory() ? rel + "/" : rel + "=" + slurp(e.path().string()));
  }
  std::sort(lines.begin(), lines.end());
  std::string out;
  for (const std::string& l : lines) out += l + "\n";
  return out;
}

const std::string kOld = "tum/\ntum/depth/\ntum/depth/1.png=old depth\ntum/rgb.txt=old list\n";
const std::string kNew = "tum/\ntum/depth/\ntum/depth/1.png=new depth\ntum/depth/2.png=new depth 2\ntum/rgb.txt=new list\n";

void writeOld(const std::string& target) {
  fs::create_directories(target + "/depth");
  std::ofstream(target + "/depth/1.png") << "old depth";
  std::ofstream(target + "/rgb.txt") << "old list";
}

// The child: an old folder, a new one written through AtomicFolder, and a commit during which
// (or, with `before`, before which) the signal comes. Ends by the signal (kEndedBySignal), or
// with 43 when a commit after the cleanup did not fail (naming the target) as it must.
[[noreturn]] void commitUnderSignal(const std::string& target, int trigger_call, bool no_exchange, bool before) {
  writeOld(target);
  AtomicFolder out(target);
  fs::create_directory(out.file("depth"));
  writeFileAtomic(out.file("depth/1.png"), "new depth");
  writeFileAtomic(out.file("depth/2.png"), "new depth 2");
  writeFileAtomic(out.file("rgb.txt"), "new list");
  g_no_exchange = no_exchange;
  if (before) {
    signalNow();
    while (!g_cleaned) std::this_thread::sleep_for(std::chrono::milliseconds(1));
    const std::string error = test::errorOf([&] { out.commit(); });
    if (error.find("cannot write " + target + ": ") == std::string::npos) g_exit_status = 43;
  } else {
    g_trigger_call = trigger_call;
    try {
      out.commit();
    } catch (const Error&) {
    }
    if (!g_signalled) signalNow();  // the commit made fewer renames: the signal comes after it
  }
  g_may_end = true;
  for (;;) pause();
}

struct Outcome {
  int status = -1;
  std::string folder;  // listing() of the folder holding the target
};

Outcome trial(const std::string& name, int trigger_call, bool no_exchange, bool before = false) {
  const std::string dir = test::tempDir("folder_commit_signal_" + name);
  const pid_t pid = fork();
  if (pid == 0) commitUnderSignal(dir + "/tum", trigger_call, no_exchange, before);
  int raw = 0;
  waitpid(pid, &raw, 0);
  return {WIFEXITED(raw) ? WEXITSTATUS(raw) : 128 + WTERMSIG(raw), listing(dir)};
}

// The signal during the commit's first rename (the exchange, or the old folder stepping aside)
// and its second: the commit finishes first, the cleanup then removes the old folder. Before the
// fix the cleanup ran between the old folder moving aside and the new one moving in, and the
// process ended with no tum/ and the old content in a temporary (which the next run deleted).
TEST(FolderCommitUnderSignal, TheTargetHoldsTheNewFolderAndNoTemporaryIsLeft) {
  for (const bool no_exchange : {false, true})
    for (const int call : {1, 2}) {
      SCOPED_TRACE(std::string(no_exchange ? "old folder stepping aside" : "exchange") + ", signal at rename " +
                   std::to_string(call));
      const Outcome o = trial("during", call, no_exchange);
      EXPECT_EQ(o.status, kEndedBySignal);
      EXPECT_EQ(o.folder, kNew) << "expected the whole new folder and nothing else";
    }
}

// A signal just before the commit: the cleanup removes the new temporary, and the commit that
// comes after it fails without touching the old folder.
TEST(FolderCommitUnderSignal, ACommitAfterTheCleanupFailsAndKeepsTheOldFolder) {
  for (const bool no_exchange : {false, true}) {
    const Outcome o = trial("before", 0, no_exchange, true);
    EXPECT_EQ(o.status, kEndedBySignal) << "43: the commit after the cleanup did not fail";
    EXPECT_EQ(o.folder, kOld);
  }
}

}  // namespace
}  // namespace vf
