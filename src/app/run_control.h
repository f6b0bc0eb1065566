#pragma once
// Stopping a long command cleanly, and reporting a chosen exit status.
#include <stdexcept>
#include <string>

namespace vf::app {

// Thrown by a command that already reported what happened and must end the process with a
// particular status (e.g. 130 after SIGINT); main() returns `status` without printing more.
struct ExitWithStatus : std::runtime_error {
  ExitWithStatus(int status, const std::string& why) : std::runtime_error(why), status(status) {}
  int status;
};

// While alive, SIGINT and SIGTERM only record themselves (the handler sets an atomic and does
// nothing else); the work loop polls received() at a point where stopping is safe. The handlers
// are one-shot (SA_RESETHAND): a second Ctrl-C terminates at once. Destruction restores the
// previous handlers.
class StopSignals {
 public:
  StopSignals();
  ~StopSignals();
  StopSignals(const StopSignals&) = delete;
  StopSignals& operator=(const StopSignals&) = delete;

  // The first signal received (SIGINT or SIGTERM), 0 while none.
  int received() const;
  // 128 + signal, the shell's convention: 130 for SIGINT, 143 for SIGTERM.
  static int exitStatus(int signal) { return 128 + signal; }
  static std::string name(int signal);
};

}  // namespace vf::app
