#include "app/progress.h"

#include <unistd.h>

#include <cstdio>

namespace vf::app {

ProgressBar::ProgressBar(int total, bool enabled)
    : total_(total), enabled_(enabled), tty_(isatty(STDERR_FILENO) != 0),
      start_(std::chrono::steady_clock::now()) {}

void ProgressBar::update(int done, const std::string& note) {
  if (!enabled_ || total_ <= 0) return;
  const double seconds =
      std::chrono::duration<double>(std::chrono::steady_clock::now() - start_).count();
  const double fps = seconds > 0 ? done / seconds : 0.0;
  const int width = 30;
  const int filled = done * width / total_;
  if (tty_) {
    std::string bar(size_t(filled), '#');
    bar.resize(size_t(width), '.');
    std::fprintf(stderr, "\r[%s] %d/%d  %.1f frames/s  %s\033[K", bar.c_str(), done, total_, fps, note.c_str());
    std::fflush(stderr);
  } else {
    const int decile = done * 10 / total_;
    if (decile != last_decile_) {
      last_decile_ = decile;
      std::fprintf(stderr, "%d/%d frames  %.1f frames/s  %s\n", done, total_, fps, note.c_str());
    }
  }
}

void ProgressBar::finish() {
  if (enabled_ && tty_) std::fprintf(stderr, "\n");
}

}  // namespace vf::app
