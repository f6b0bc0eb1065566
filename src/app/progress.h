#pragma once
// A one-line progress bar on stderr: on a terminal it is redrawn in place with the rate (frames/s,
// or any other unit), the time elapsed and an estimate of the time left; otherwise a line is
// printed every tenth of the run so that logs stay short (and free of estimates that a log reader
// cannot use).
#include <chrono>
#include <string>

namespace vf::app {

class ProgressBar {
 public:
  ProgressBar(int total, bool enabled, std::string unit = "frames");
  void update(int done, const std::string& note = "");
  void finish();

 private:
  int total_;
  bool enabled_, tty_;
  std::string unit_;
  int last_decile_ = -1;
  std::chrono::steady_clock::time_point start_;
};

// Seconds from t0 to now, for the times commands print.
inline double secondsSince(std::chrono::steady_clock::time_point t0) {
  return std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count();
}

// "0:41", "12:05", "1:02:09": a duration the way a clock shows it.
std::string clockDuration(double seconds);
// The time left at a constant rate; empty while too little is done for the rate to mean anything.
std::string estimatedTimeLeft(int done, int total, double elapsed_s);

}  // namespace vf::app
