#pragma once
// Running the vdbfuse binary of this build from tests: with its output captured, optionally under
// a file-size limit (a full disk: RLIMIT_FSIZE with SIGXFSZ ignored, so that writes fail with
// EFBIG instead of killing the process), or in the background for signals. Plus the checks every
// fault test makes on a folder: no temporary left, an input unchanged.
#include <fcntl.h>
#include <signal.h>
#include <sys/resource.h>
#include <sys/stat.h>
#include <sys/wait.h>
#include <unistd.h>

#include <algorithm>
#include <chrono>
#include <cstdlib>
#include <filesystem>
#include <fstream>
#include <sstream>
#include <string>
#include <thread>
#include <vector>

namespace vf::test {

// This build's vdbfuse; VDBFUSE_EXE, where set, names another (to show what an older one does).
inline const std::string& vdbfuseExe() {
  static const std::string exe = [] {
    const char* other = std::getenv("VDBFUSE_EXE");
    return other && *other ? std::string(other) : std::string(VDBFUSE_BINARY_DIR) + "/src/app/vdbfuse";
  }();
  return exe;
}

struct CliRun {
  int status = -1;     // exit status, or 128 + signal
  std::string output;  // stdout and stderr together
  double seconds = 0;  // wall time
  // CPU time (user + system) of the run: what "it ends promptly" bounds where a loaded machine
  // stretches the wall time (a hang shows as the wall-clock timeout's kill instead).
  double cpu_seconds = 0;
};

// Child side: limits, then exec. file_size_limit 0 = none.
[[noreturn]] inline void execVdbfuse(const std::vector<std::string>& args, uint64_t file_size_limit, int out_fd) {
  dup2(out_fd, 1);
  dup2(out_fd, 2);
  if (file_size_limit > 0) {
    signal(SIGXFSZ, SIG_IGN);  // inherited through exec: writes past the limit fail with EFBIG
    const rlimit limit{file_size_limit, file_size_limit};
    setrlimit(RLIMIT_FSIZE, &limit);
  }
  std::vector<char*> argv{const_cast<char*>(vdbfuseExe().c_str())};
  for (const std::string& a : args) argv.push_back(const_cast<char*>(a.c_str()));
  argv.push_back(nullptr);
  execv(vdbfuseExe().c_str(), argv.data());
  _exit(127);
}

inline int statusOf(int raw) { return WIFEXITED(raw) ? WEXITSTATUS(raw) : 128 + WTERMSIG(raw); }

// A test's common arguments followed by one case's own.
inline std::vector<std::string> withArgs(std::vector<std::string> base, const std::vector<std::string>& extra) {
  base.insert(base.end(), extra.begin(), extra.end());
  return base;
}

// Runs vdbfuse to the end; a run longer than timeout_s is killed (status 128 + SIGKILL).
inline CliRun runVdbfuse(const std::vector<std::string>& args, uint64_t file_size_limit = 0, double timeout_s = 300) {
  int fds[2];
  if (pipe(fds) != 0) return {};
  const auto t0 = std::chrono::steady_clock::now();
  const pid_t pid = fork();
  if (pid == 0) {
    close(fds[0]);
    execVdbfuse(args, file_size_limit, fds[1]);
  }
  close(fds[1]);
  fcntl(fds[0], F_SETFL, O_NONBLOCK);
  CliRun run;
  char buf[4096];
  int raw = 0;
  rusage usage{};
  for (bool done = false; !done;) {
    ssize_t n;
    while ((n = read(fds[0], buf, sizeof buf)) > 0) run.output.append(buf, size_t(n));
    done = wait4(pid, &raw, WNOHANG, &usage) == pid;
    if (!done && std::chrono::steady_clock::now() - t0 > std::chrono::duration<double>(timeout_s)) {
      kill(pid, SIGKILL);
      wait4(pid, &raw, 0, &usage);
      done = true;
    }
    if (!done) std::this_thread::sleep_for(std::chrono::milliseconds(2));
  }
  ssize_t n;
  while ((n = read(fds[0], buf, sizeof buf)) > 0) run.output.append(buf, size_t(n));
  close(fds[0]);
  run.status = statusOf(raw);
  run.seconds = std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count();
  run.cpu_seconds = double(usage.ru_utime.tv_sec + usage.ru_stime.tv_sec) +
                    1e-6 * double(usage.ru_utime.tv_usec + usage.ru_stime.tv_usec);
  return run;
}

// A run in the background, its output going to `log`; for tests that signal it.
struct BackgroundRun {
  pid_t pid = -1;
  std::string log;
  BackgroundRun(const std::vector<std::string>& args, std::string log_path) : log(std::move(log_path)) {
    const int fd = open(log.c_str(), O_WRONLY | O_CREAT | O_TRUNC, 0644);
    pid = fork();
    if (pid == 0) execVdbfuse(args, 0, fd);
    close(fd);
  }
  int wait() {
    int raw = 0;
    waitpid(pid, &raw, 0);
    pid = -1;
    return statusOf(raw);
  }
  // Whether the process has ended (it stays waitable).
  bool ended() const {
    siginfo_t info{};
    return waitid(P_PID, id_t(pid), &info, WEXITED | WNOHANG | WNOWAIT) == 0 && info.si_pid != 0;
  }
  std::string output() const {
    std::ifstream in(log);
    std::ostringstream s;
    s << in.rdbuf();
    return s.str();
  }
  // Waits until the output contains `text`; false after timeout_s or when the process ended.
  bool waitForOutput(const std::string& text, double timeout_s = 120) const {
    const auto deadline = std::chrono::steady_clock::now() + std::chrono::duration<double>(timeout_s);
    while (std::chrono::steady_clock::now() < deadline) {
      if (output().find(text) != std::string::npos) return true;
      if (ended()) return output().find(text) != std::string::npos;
      std::this_thread::sleep_for(std::chrono::milliseconds(2));
    }
    return false;
  }
  ~BackgroundRun() {
    if (pid > 0) {
      kill(pid, SIGKILL);
      waitpid(pid, nullptr, 0);
    }
  }
};

inline std::string fileContent(const std::string& path) {
  std::ifstream in(path, std::ios::binary);
  std::ostringstream s;
  s << in.rdbuf();
  return s.str();
}

inline void writeText(const std::string& path, const std::string& text) {
  std::ofstream(path, std::ios::binary) << text;
}

// Temporaries (".name.tmpPID_N...") anywhere under `dir`.
inline std::vector<std::string> temporariesUnder(const std::string& dir) {
  std::vector<std::string> found;
  for (const auto& e : std::filesystem::recursive_directory_iterator(dir)) {
    const std::string name = e.path().filename().string();
    if (name.size() > 1 && name[0] == '.' && name.find(".tmp") != std::string::npos) found.push_back(e.path().string());
  }
  return found;
}

// OpenVDB gives every file a new UUID (header bytes 21..56): equal scenes differ only there.
inline std::string withoutVdbUuid(const std::string& path, std::string bytes) {
  if (std::filesystem::path(path).extension() == ".vdb" && bytes.size() > 57)
    std::fill(bytes.begin() + 21, bytes.begin() + 57, '0');
  return bytes;
}

// Every file under `dir` with its bytes, to show that a failed command changed nothing.
inline std::vector<std::pair<std::string, std::string>> snapshot(const std::string& dir) {
  std::vector<std::pair<std::string, std::string>> files;
  for (const auto& e : std::filesystem::recursive_directory_iterator(dir))
    if (e.is_regular_file()) files.emplace_back(e.path().string(), fileContent(e.path().string()));
  std::sort(files.begin(), files.end());
  return files;
}

// Paths whose bytes differ between two snapshots, or that are in only one of them.
inline std::vector<std::string> changedFiles(const std::vector<std::pair<std::string, std::string>>& before,
                                             const std::vector<std::pair<std::string, std::string>>& after) {
  std::vector<std::string> changed;
  for (const auto& [path, bytes] : before) {
    const auto it = std::find_if(after.begin(), after.end(), [&](const auto& f) { return f.first == path; });
    if (it == after.end() || it->second != bytes) changed.push_back(path);
  }
  for (const auto& [path, bytes] : after)
    if (std::none_of(before.begin(), before.end(), [&](const auto& f) { return f.first == path; }))
      changed.push_back(path);
  return changed;
}

}  // namespace vf::test
