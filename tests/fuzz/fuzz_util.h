#pragma once
// Shared by the fuzz targets: readers that take a path get the input through a per-process temp
// file (rewritten for every input), and vf::Error is the one exception a reader may throw.
// Any other exception escapes the entry point and aborts: that is a finding (readers must turn
// every failure into a vf::Error naming the file).
#include <unistd.h>

#include <cstdint>
#include <cstdio>
#include <cstdlib>
#include <string>

namespace vf::fuzz {

// A file in $TMPDIR (or /tmp) named after the process, so parallel fuzzers do not collide.
inline std::string writeTempInput(const char* suffix, const uint8_t* data, size_t size) {
  const char* dir = std::getenv("TMPDIR");
  const std::string path = std::string(dir && *dir ? dir : "/tmp") + "/vdbfuse_fuzz_" +
                           std::to_string(::getpid()) + suffix;
  std::FILE* f = std::fopen(path.c_str(), "wb");
  if (!f) std::abort();  // the harness itself failed; not a reader finding
  if (size != 0 && std::fwrite(data, 1, size, f) != size) std::abort();
  std::fclose(f);
  return path;
}

}  // namespace vf::fuzz
