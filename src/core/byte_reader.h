#pragma once
// Bounds-checked reads from bytes in memory (binary files: checkpoints, .vdb structure checks).
// Running out of bytes, or a seek outside them, throws vf::Error with the reader's context, the
// byte offset and what was being read, so that a damaged file is named, never over-read.
#include <cstdint>
#include <cstring>
#include <string>
#include <type_traits>

#include "core/error.h"

namespace vf {

class ByteReader {
 public:
  // context opens every error message, e.g. "scene.vdb: damaged or unsupported .vdb file".
  ByteReader(const uint8_t* data, size_t size, std::string context)
      : data_(data), size_(size), context_(std::move(context)) {}

  [[noreturn]] void fail(const std::string& what) const {
    throw Error(context_ + " (byte " + std::to_string(pos_) + "): " + what);
  }
  size_t offset() const { return pos_; }
  size_t size() const { return size_; }
  uint64_t remaining() const { return size_ - pos_; }
  bool atEnd() const { return pos_ == size_; }

  const uint8_t* take(uint64_t n, const std::string& what) {
    if (n > remaining())
      fail(what + " needs " + std::to_string(n) + " bytes, " + std::to_string(remaining()) + " are left");
    const uint8_t* p = data_ + pos_;
    pos_ += size_t(n);
    return p;
  }
  template <class T>
  T read(const std::string& what) {
    static_assert(std::is_trivially_copyable_v<T>);
    T value;
    std::memcpy(&value, take(sizeof(T), what), sizeof(T));
    return value;
  }
  // A uint32 length and that many bytes (OpenVDB's io::readString, the checkpoint's strings).
  std::string readString(const std::string& what) {
    const uint32_t n = read<uint32_t>(what + " length");
    const uint8_t* p = take(n, what);
    return std::string(reinterpret_cast<const char*>(p), n);
  }
  void seek(int64_t pos, const std::string& what) {
    if (pos < 0 || uint64_t(pos) > size_)
      fail(what + " points to byte " + std::to_string(pos) + ", outside the " + std::to_string(size_) + " bytes");
    pos_ = size_t(pos);
  }

 private:
  const uint8_t* data_;
  size_t size_;
  std::string context_;
  size_t pos_ = 0;
};

}  // namespace vf
