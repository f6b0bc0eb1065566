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

}  // namespace vf
