#pragma once
// A one-line progress bar with frames/s on stderr (redrawn in place on a terminal, printed every
// tenth of the run otherwise so logs stay short).
#include <chrono>
#include <string>

namespace vf::app {

class ProgressBar {
 public:
  ProgressBar(int total, bool enabled);
  void update(int done, const std::string& note = "");
  void finish();

 private:
  int total_;
  bool enabled_, tty_;
  int last_decile_ = -1;
  std::chrono::steady_clock::time_point start_;
};

}  // namespace vf::app
