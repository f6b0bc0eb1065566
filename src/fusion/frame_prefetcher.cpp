#include "fusion/frame_prefetcher.h"

#include <algorithm>
#include <thread>

namespace vf {

FramePrefetcher::FramePrefetcher(const FrameSource& source, int first, int count, int depth, int workers)
    : source_(source), next_to_claim_(first), next_to_deliver_(first), end_index_(first + std::max(count, 0)),
      depth_(std::max({depth, workers, 1})) {
  const int threads = std::min(std::max(workers, 1), std::max(count, 0));
  for (int w = 0; w < threads; ++w) workers_.emplace_back([this] { run(); });
}

FramePrefetcher::~FramePrefetcher() {
  {
    std::lock_guard<std::mutex> lock(mutex_);
    stop_ = true;
  }
  changed_.notify_all();
  for (std::thread& worker : workers_) worker.join();
}

void FramePrefetcher::run() {
  for (;;) {
    int index;
    {
      std::unique_lock<std::mutex> lock(mutex_);
      changed_.wait(lock, [&] {
        return stop_ || next_to_claim_ >= end_index_ || next_to_claim_ < next_to_deliver_ + depth_;
      });
      if (stop_ || next_to_claim_ >= end_index_) return;
      index = next_to_claim_++;
    }
    Slot slot;
    try {
      slot.frame = source_.load(index);
    } catch (...) {
      slot.error = std::current_exception();
    }
    {
      std::lock_guard<std::mutex> lock(mutex_);
      ready_.emplace(index, std::move(slot));
    }
    changed_.notify_all();
  }
}

std::optional<RgbdFrame> FramePrefetcher::next() {
  std::unique_lock<std::mutex> lock(mutex_);
  if (next_to_deliver_ >= end_index_) return std::nullopt;
  changed_.wait(lock, [&] { return ready_.count(next_to_deliver_) > 0; });
  const auto it = ready_.find(next_to_deliver_);
  Slot slot = std::move(it->second);
  ready_.erase(it);
  ++next_to_deliver_;
  lock.unlock();
  changed_.notify_all();
  if (slot.error) std::rethrow_exception(slot.error);
  return std::move(slot.frame);
}

int FramePrefetcher::workersFor(Device device) {
  if (device != Device::Cuda) return 1;
  const unsigned cores = std::thread::hardware_concurrency();
  return int(std::clamp(cores > 1 ? cores - 1 : 1u, 1u, 8u));
}

}  // namespace vf
