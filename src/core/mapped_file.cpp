#include "core/mapped_file.h"

#include <fcntl.h>
#include <sys/mman.h>
#include <sys/stat.h>
#include <unistd.h>

#include <cerrno>
#include <cstring>
#include <string>

#include "core/error.h"

namespace vf {
namespace {

// O_NONBLOCK: opening a FIFO for reading would otherwise wait for a writer.
int openRegular(const std::string& path, const std::string& what, size_t& size) {
  const int fd = ::open(path.c_str(), O_RDONLY | O_CLOEXEC | O_NONBLOCK);
  if (fd < 0 && errno == ENOENT) throw Error(path + ": the " + what + " does not exist");
  if (fd < 0) throw Error(path + ": cannot open " + what + ": " + std::strerror(errno));
  struct stat st {};
  if (::fstat(fd, &st) != 0 || !S_ISREG(st.st_mode)) {
    ::close(fd);
    throw Error(path + ": the " + what + " is not a regular file");
  }
  size = size_t(st.st_size);
  return fd;
}

}  // namespace

void requireRegularFile(const std::string& path, const std::string& what) {
  size_t size = 0;
  ::close(openRegular(path, what, size));
}

std::string readRegularFile(const std::string& path, const std::string& what, size_t max_bytes) {
  size_t size = 0;
  const int fd = openRegular(path, what, size);
  if (size > max_bytes) {
    ::close(fd);
    throw Error(path + ": the " + what + " is " + std::to_string(size) + " bytes, more than the " +
                std::to_string(max_bytes) + " a " + what + " may have");
  }
  std::string bytes(size, '\0');
  size_t done = 0;
  while (done < size) {
    const ssize_t n = ::read(fd, &bytes[done], size - done);
    if (n < 0 && errno == EINTR) continue;
    if (n <= 0) {
      const int err = n < 0 ? errno : 0;
      ::close(fd);
      throw Error(path + ": cannot read the " + what + (err ? std::string(": ") + std::strerror(err) : ": it ended early"));
    }
    done += size_t(n);
  }
  ::close(fd);
  return bytes;
}

MappedFile::MappedFile(const std::string& path, const std::string& what) {
  const int fd = openRegular(path, what, size_);
  if (size_ > 0) {
    void* p = ::mmap(nullptr, size_, PROT_READ, MAP_PRIVATE, fd, 0);
    if (p == MAP_FAILED) {
      const int err = errno;
      ::close(fd);
      throw Error(path + ": cannot map " + what + ": " + std::strerror(err));
    }
    data_ = static_cast<const uint8_t*>(p);
  }
  ::close(fd);
}

MappedFile::~MappedFile() {
  if (data_) ::munmap(const_cast<uint8_t*>(data_), size_);
}

}  // namespace vf
