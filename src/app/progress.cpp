#include "app/progress.h"

#include <unistd.h>

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <utility>

namespace vf::app {

std::string clockDuration(double seconds) {
  const long total = std::lround(std::max(0.0, seconds));
  const long h = total / 3600, m = total / 60 % 60, s = total % 60;
  char text[32];
  if (h > 0)
    std::snprintf(text, sizeof text, "%ld:%02ld:%02ld", h, m, s);
  else
    std::snprintf(text, sizeof text, "%ld:%02ld", m, s);
  return text;
}

std::string estimatedTimeLeft(int done, int total, double elapsed_s) {
  // The first frames carry start-up costs (allocation, the first keyframes): wait for a few
  // percent of the run and a second of work before extrapolating.
  if (done <= 0 || total <= 0 || done >= total || elapsed_s < 1.0 || done * 50 < total) return "";
  return clockDuration(elapsed_s * double(total - done) / double(done));
}

ProgressBar::ProgressBar(int total, bool enabled, std::string unit)
    : total_(total), enabled_(enabled), tty_(isatty(STDERR_FILENO) != 0), unit_(std::move(unit)),
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
    const std::string left = estimatedTimeLeft(done, total_, seconds);
    std::fprintf(stderr, "\r[%s] %d/%d  %.1f %s/s  %s elapsed%s%s  %s\033[K", bar.c_str(), done, total_, fps, unit_.c_str(),
                 clockDuration(seconds).c_str(), left.empty() ? "" : ", about ", left.empty() ? "" : (left + " left").c_str(),
                 note.c_str());
    std::fflush(stderr);
  } else {
    const int decile = done * 10 / total_;
    if (decile != last_decile_) {
      last_decile_ = decile;
      std::fprintf(stderr, "%d/%d %s  %.1f %s/s  %s\n", done, total_, unit_.c_str(), fps, unit_.c_str(), note.c_str());
    }
  }
}

void ProgressBar::finish() {
  if (enabled_ && tty_) std::fprintf(stderr, "\n");
}

}  // namespace vf::app
