#pragma once
// Read-only access to a zip archive (libzip), shared by threads: entry bytes are read under a
// mutex (libzip handles are not thread-safe) and callers decode them outside it, in parallel.
#include <cstdint>
#include <memory>
#include <mutex>
#include <string>
#include <unordered_map>
#include <vector>

namespace vf {

class ZipArchive {
 public:
  // Opens `path`; throws vf::Error naming it when it is missing, not a zip, or truncated.
  explicit ZipArchive(const std::string& path);
  ~ZipArchive();
  ZipArchive(const ZipArchive&) = delete;
  ZipArchive& operator=(const ZipArchive&) = delete;

  const std::string& path() const { return path_; }
  // Entry names in archive order.
  const std::vector<std::string>& entryNames() const { return names_; }
  bool contains(const std::string& entry) const { return index_.count(entry) != 0; }
  // Uncompressed size as recorded in the central directory; throws if the entry is missing.
  uint64_t entrySize(const std::string& entry) const;
  // The entry's uncompressed bytes; throws vf::Error naming archive and entry when it is missing,
  // larger than max_bytes, or cannot be read in full (CRC or truncation errors). Thread-safe.
  std::vector<uint8_t> read(const std::string& entry, uint64_t max_bytes = uint64_t(1) << 30) const;

 private:
  struct Handle;
  std::string path_;
  std::unique_ptr<Handle> handle_;
  std::vector<std::string> names_;
  std::unordered_map<std::string, uint64_t> index_;  // name -> libzip index
  mutable std::mutex mutex_;
};

}  // namespace vf
