#include "io/zip_archive.h"

#include <zip.h>

#include "core/error.h"
#include "core/mapped_file.h"

namespace vf {

struct ZipArchive::Handle {
  zip_t* zip = nullptr;
  ~Handle() {
    if (zip) zip_discard(zip);  // read-only: nothing to write back
  }
};

namespace {

std::string libzipMessage(int code) {
  zip_error_t error;
  zip_error_init_with_code(&error, code);
  std::string message = zip_error_strerror(&error);
  zip_error_fini(&error);
  return message;
}

}  // namespace

ZipArchive::ZipArchive(const std::string& path) : path_(path), handle_(std::make_unique<Handle>()) {
  requireRegularFile(path, "zip archive");  // libzip would wait on a FIFO
  int code = 0;
  // ZIP_CHECKCONS makes libzip compare the central directory with the local headers, which
  // catches archives cut short or patched in the middle before any entry is read.
  handle_->zip = zip_open(path.c_str(), ZIP_RDONLY | ZIP_CHECKCONS, &code);
  if (!handle_->zip)
    throw Error(path + ": cannot open as a zip archive (" + libzipMessage(code) + ")");
  const zip_int64_t n = zip_get_num_entries(handle_->zip, 0);
  if (n < 0) throw Error(path + ": cannot list zip entries");
  names_.reserve(size_t(n));
  for (zip_int64_t i = 0; i < n; ++i) {
    const char* name = zip_get_name(handle_->zip, zip_uint64_t(i), ZIP_FL_ENC_RAW);
    if (!name) throw Error(path + ": unreadable name of zip entry " + std::to_string(i));
    names_.emplace_back(name);
    index_.emplace(names_.back(), uint64_t(i));
  }
}

ZipArchive::~ZipArchive() = default;

uint64_t ZipArchive::entrySize(const std::string& entry) const {
  const auto it = index_.find(entry);
  if (it == index_.end()) throw Error(path_ + ": no entry '" + entry + "' in the archive");
  std::lock_guard<std::mutex> lock(mutex_);
  zip_stat_t st;
  zip_stat_init(&st);
  if (zip_stat_index(handle_->zip, it->second, 0, &st) != 0 || !(st.valid & ZIP_STAT_SIZE))
    throw Error(path_ + ": cannot stat entry '" + entry + "'");
  return st.size;
}

std::vector<uint8_t> ZipArchive::read(const std::string& entry, uint64_t max_bytes) const {
  const auto it = index_.find(entry);
  if (it == index_.end()) throw Error(path_ + ": no entry '" + entry + "' in the archive");
  const uint64_t size = entrySize(entry);
  if (size > max_bytes)
    throw Error(path_ + ": entry '" + entry + "' claims " + std::to_string(size) +
                " bytes, more than the limit of " + std::to_string(max_bytes));
  std::vector<uint8_t> bytes(size_t(size) + 1);  // one spare byte detects an entry longer than said
  std::lock_guard<std::mutex> lock(mutex_);
  zip_file_t* file = zip_fopen_index(handle_->zip, it->second, 0);
  if (!file)
    throw Error(path_ + ": cannot open entry '" + entry + "' (" +
                zip_strerror(handle_->zip) + ")");
  size_t got = 0;
  std::string problem;
  while (got < bytes.size()) {
    const zip_int64_t r = zip_fread(file, bytes.data() + got, bytes.size() - got);
    if (r < 0) {
      problem = zip_file_strerror(file);
      break;
    }
    if (r == 0) break;
    got += size_t(r);
  }
  zip_fclose(file);
  if (!problem.empty())
    throw Error(path_ + ": cannot read entry '" + entry + "' (" + problem + ")");
  if (got != size)
    throw Error(path_ + ": entry '" + entry + "' has " + std::to_string(got) +
                " bytes, the directory says " + std::to_string(size));
  bytes.resize(got);
  return bytes;
}

}  // namespace vf
