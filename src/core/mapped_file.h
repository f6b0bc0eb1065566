#pragma once
// A whole regular file mapped read-only: binary readers (checkpoints, the .vdb structure check)
// walk it with a ByteReader without copying it. Anything but a regular file (a FIFO, a device,
// a folder) is refused before it is read, so that no reader can hang on it or read it forever.
#include <cstddef>
#include <cstdint>
#include <string>

namespace vf {

class MappedFile {
 public:
  // what: how messages name the file ("scene file", "checkpoint").
  MappedFile(const std::string& path, const std::string& what);
  ~MappedFile();
  MappedFile(const MappedFile&) = delete;
  MappedFile& operator=(const MappedFile&) = delete;

  const uint8_t* data() const { return data_; }
  size_t size() const { return size_; }

 private:
  const uint8_t* data_ = nullptr;
  size_t size_ = 0;
};

// Throws vf::Error naming `path` unless it is a regular file (opened without blocking on FIFOs).
void requireRegularFile(const std::string& path, const std::string& what);

// The bound of every text input (lists, trajectories, class tables, calibration, metadata): far
// above any real one (TUM's longest ground truth is a few MB), far below what would exhaust memory.
constexpr size_t kMaxTextFileBytes = size_t(256) << 20;

// The whole of a regular file, for every reader that takes a file in one piece: a FIFO, a device
// (/dev/zero) or a folder is refused before anything is read, and so is a file over max_bytes.
// Throws vf::Error naming `path` and `what` ("class table").
std::string readRegularFile(const std::string& path, const std::string& what, size_t max_bytes);

}  // namespace vf
