#pragma once
// Where tests find the shared real captures. A test that needs data calls requireData(), which
// fails (never skips) with the path it looked for, so a missing ../shared is loud in CI.
#include <gtest/gtest.h>

#include <cstdio>
#include <cstdlib>
#include <filesystem>
#include <functional>
#include <string>

#include "core/error.h"

namespace vf::test {

// The environment variable VDBFUSE_DATA_DIR, where set, wins over the folder compiled in: the
// GPU bundle (scripts/gpu_bundle.sh) carries its own compact copy of the captures.
inline std::string dataPath(const std::string& relative) {
  const char* override_dir = std::getenv("VDBFUSE_DATA_DIR");
  return std::string(override_dir && *override_dir ? override_dir : VDBFUSE_DATA_DIR) + "/" + relative;
}

// Returns the absolute path, or records a fatal failure naming it when it does not exist.
#define VF_REQUIRE_DATA(var, relative)                                                  \
  const std::string var = ::vf::test::dataPath(relative);                               \
  ASSERT_TRUE(std::filesystem::exists(var))                                             \
      << "test data not found: " << var                                                 \
      << " (the shared data folder must sit beside the project as ../shared/data)"

// The message of the vf::Error that f throws, or "(no error)" when it throws none.
inline std::string errorOf(const std::function<void()>& f) {
  try {
    f();
  } catch (const Error& e) {
    return e.what();
  }
  return "(no error)";
}

// Runs a shell command; returns its stdout and stderr together and sets status (pclose's).
inline std::string runCommand(const std::string& command, int& status) {
  std::string out;
  FILE* pipe = popen((command + " 2>&1").c_str(), "r");
  char buf[4096];
  while (pipe && fgets(buf, sizeof buf, pipe)) out += buf;
  status = pipe ? pclose(pipe) : -1;
  return out;
}

// `command` wrapped for xvfb-run (the path to it): run in a shell under a fresh virtual X server
// that prints its own exit status last, for xvfbExitStatus to read. xvfb-run's status cannot be
// trusted: it returns 5 of its own when removing its temp folder fails (seen with parallel runs).
inline std::string underXvfb(const std::string& xvfb_run, const std::string& command) {
  std::string quoted = "'";
  for (const char c : command + "; echo vf_exit=$?") quoted += c == '\'' ? std::string("'\\''") : std::string(1, c);
  return xvfb_run + " -a -s '-screen 0 1280x1024x24' sh -c " + quoted + "'";
}

// The exit status underXvfb's command printed, or -1 when it printed none (X did not start).
inline int xvfbExitStatus(const std::string& output) {
  const size_t at = output.rfind("vf_exit=");
  return at == std::string::npos ? -1 : std::atoi(output.c_str() + at + 8);
}

// A fresh folder for one test's files, /tmp/vdbfuse_test_<build hash>_NAME: two builds' suites
// running on one machine (a developer's and CI's, two worktrees) never empty each other's
// folders mid-test, and a build reuses its own folders run after run, so nothing piles up.
inline std::string tempDir(const std::string& name) {
  std::string prefix = "vdbfuse_test_";
#ifdef VDBFUSE_BINARY_DIR
  const std::string build_dir = VDBFUSE_BINARY_DIR;
  char hash[32];
  std::snprintf(hash, sizeof hash, "%08zx_", std::hash<std::string>{}(build_dir) & 0xffffffffu);
  prefix += hash;
#endif
  auto dir = std::filesystem::temp_directory_path() / (prefix + name);
  std::filesystem::remove_all(dir);
  std::filesystem::create_directories(dir);
  return dir.string();
}

}  // namespace vf::test
