#include "app/run_control.h"

#include <pthread.h>
#include <signal.h>
#include <unistd.h>

#include <atomic>
#include <cstdio>
#include <mutex>
#include <thread>

#include "core/atomic_output.h"

namespace vf::app {
namespace {

std::atomic<int> g_stop_signal{0};
std::atomic<bool> g_graceful{false};
std::atomic<bool> g_terminating{false};
std::mutex g_message_mutex;
std::string g_stop_message;

sigset_t stopSignalSet() {
  sigset_t set;
  sigemptyset(&set);
  sigaddset(&set, SIGINT);
  sigaddset(&set, SIGTERM);
  return set;
}

[[noreturn]] void terminateBy(int signal) {
  g_terminating = true;
  removeAllPendingOutputs();
  // Die of the signal itself, so that the parent sees what happened (status 128 + signal).
  struct sigaction action {};
  action.sa_handler = SIG_DFL;
  sigemptyset(&action.sa_mask);
  sigaction(signal, &action, nullptr);
  const sigset_t set = stopSignalSet();
  pthread_sigmask(SIG_UNBLOCK, &set, nullptr);
  raise(signal);
  _exit(128 + signal);  // not reached
}

void handleSignals() {
  const sigset_t set = stopSignalSet();
  for (;;) {
    int signal = 0;
    if (sigwait(&set, &signal) != 0) continue;
    if (!g_graceful.load()) terminateBy(signal);
    int expected = 0;
    if (g_stop_signal.compare_exchange_strong(expected, signal)) {
      std::lock_guard<std::mutex> lock(g_message_mutex);
      std::fprintf(stderr, "\n%s: %s\n", StopSignals::name(signal).c_str(), g_stop_message.c_str());
    } else {
      std::fprintf(stderr, "\n%s: still saving, please wait\n", StopSignals::name(signal).c_str());
    }
  }
}

}  // namespace

void startSignalThread() {
  const sigset_t set = stopSignalSet();
  pthread_sigmask(SIG_BLOCK, &set, nullptr);
  std::thread(handleSignals).detach();
}

void awaitSignalTermination() {
  if (!g_terminating.load()) return;
  // The signal thread ends the process by the signal once the outputs are gone; until then this
  // thread must neither report nor exit (signals stay blocked here, so pause() only waits).
  for (;;) pause();
}

void restoreSignalMask() {
  const sigset_t set = stopSignalSet();
  pthread_sigmask(SIG_UNBLOCK, &set, nullptr);
}

StopSignals::StopSignals(std::string message) {
  {
    std::lock_guard<std::mutex> lock(g_message_mutex);
    g_stop_message = std::move(message);
  }
  g_stop_signal = 0;
  g_graceful = true;
}

StopSignals::~StopSignals() { g_graceful = false; }

int StopSignals::received() const { return g_stop_signal.load(); }

std::string StopSignals::name(int signal) {
  if (signal == SIGINT) return "SIGINT";
  if (signal == SIGTERM) return "SIGTERM";
  return "signal " + std::to_string(signal);
}

}  // namespace vf::app
