#pragma once
// Per-stage times of every frame, for the timing table and the benchmark medians.
//
// On the CPU a stage's time is the host's wall clock from its start to its end. On the GPU the
// host only queues work and returns (cuda/parallel.cuh), so the wall clock would time the
// queueing, and the wait would land on whichever stage first reads a result back. A CUDA stage
// is instead bracketed by two events on the GPU's stream and its time is the GPU clock between
// them, read once the GPU has passed the second (without waiting, as later stages start; or
// waiting, when the samples are read).
#include <chrono>
#include <map>
#include <string>
#include <vector>

#include "fusion/device.h"

namespace vf {

class StageTimer {
 public:
  StageTimer() = default;
  // A copy holds the samples measured so far (the original's GPU spans are waited for first).
  StageTimer(const StageTimer& other);
  StageTimer& operator=(const StageTimer& other);
  ~StageTimer();

  void add(const std::string& stage, double ms);
  // A GPU stage between two events recorded on the stream (taken from takeEvent()); its sample
  // is added once the GPU has passed `end`.
  void addDeviceSpan(const std::string& stage, void* start, void* end);
  void* takeEvent();

  const std::vector<std::string>& stages() const { return order_; }
  const std::vector<double>& samples(const std::string& stage) const;
  double median(const std::string& stage) const;
  double mean(const std::string& stage) const;
  double total(const std::string& stage) const;

 private:
  struct DeviceSpan {
    std::string stage;
    void* start;
    void* end;
  };
  // Turns the GPU spans the GPU has finished into samples, in the order they were queued;
  // `wait`: all of them, waiting for the GPU.
  void resolve(bool wait) const;
  void releaseEvents() noexcept;

  std::vector<std::string> order_;
  mutable std::map<std::string, std::vector<double>> series_;
  mutable std::vector<DeviceSpan> pending_;
  mutable std::vector<void*> spare_events_;
};

// Adds the time from construction to destruction to one stage: the host's clock on the CPU, the
// GPU's between two events on the stream for Device::Cuda.
class ScopedStage {
 public:
  ScopedStage(StageTimer& timer, std::string stage, Device device = Device::Cpu);
  ~ScopedStage();
  ScopedStage(const ScopedStage&) = delete;
  ScopedStage& operator=(const ScopedStage&) = delete;

 private:
  StageTimer& timer_;
  std::string stage_;
  std::chrono::steady_clock::time_point start_;
  void* start_event_ = nullptr;  // Device::Cuda only
};

}  // namespace vf
