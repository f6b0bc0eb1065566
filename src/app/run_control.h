#pragma once
// Stopping a command cleanly, and reporting a chosen exit status.
//
// SIGINT and SIGTERM never interrupt vdbfuse's threads: startSignalThread() (first thing in
// main) blocks them in every thread and hands them to one thread of their own, which acts in
// normal context (no async-signal-safety limits):
//   - by default it removes every output still being written (core/atomic_output.h) and ends the
//     process by the signal, so an interrupted mesh, edit or convert leaves the old outputs as
//     they were and no temporary behind;
//   - while a StopSignals object lives (reconstruct's frame loop), the first signal only asks the
//     loop to stop after the current frame and save; later ones are answered with "still saving"
//     and otherwise ignored, so a second Ctrl-C never loses the run.
#include <stdexcept>
#include <string>

namespace vf::app {

// Thrown by a command that already reported what happened and must end the process with a
// particular status (e.g. 130 after SIGINT); main() returns `status` without printing more.
struct ExitWithStatus : std::runtime_error {
  ExitWithStatus(int status, const std::string& why) : std::runtime_error(why), status(status) {}
  int status;
};

// Blocks SIGINT and SIGTERM in the calling thread (and so in every thread started after it) and
// starts the thread that handles them. Call before any other thread exists.
void startSignalThread();
// Returns at once unless a signal is ending the process; then it never returns. main() calls it
// before reporting an error or returning: removing the outputs makes a running command fail (its
// temporary vanished), and that failure must neither be printed nor end the process with its own
// status in place of the signal's.
void awaitSignalTermination();
// Unblocks them again in this thread, e.g. before exec() hands the process to another program.
void restoreSignalMask();

class StopSignals {
 public:
  // message: printed by the signal thread when the first signal arrives.
  explicit StopSignals(std::string message);
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
