#include "fusion/frame_prefetcher.h"

namespace vf {

FramePrefetcher::FramePrefetcher(const FrameSource& source, int first, int count, int depth)
    : source_(source), next_index_(first), end_index_(first + count), depth_(size_t(depth)),
      total_(count), worker_([this] { run(); }) {}

FramePrefetcher::~FramePrefetcher() {
  {
    std::lock_guard<std::mutex> lock(mutex_);
    stop_ = true;
  }
  changed_.notify_all();
  worker_.join();
}

void FramePrefetcher::run() {
  for (int i = next_index_; i < end_index_; ++i) {
    {
      std::unique_lock<std::mutex> lock(mutex_);
      changed_.wait(lock, [&] { return stop_ || ready_.size() < depth_; });
      if (stop_) return;
    }
    Slot slot;
    try {
      slot.frame = source_.load(i);
    } catch (...) {
      slot.error = std::current_exception();
    }
    {
      std::lock_guard<std::mutex> lock(mutex_);
      ready_.push_back(std::move(slot));
    }
    changed_.notify_all();
  }
}

std::optional<RgbdFrame> FramePrefetcher::next() {
  std::unique_lock<std::mutex> lock(mutex_);
  if (consumed_ >= total_) return std::nullopt;
  changed_.wait(lock, [&] { return !ready_.empty(); });
  Slot slot = std::move(ready_.front());
  ready_.pop_front();
  ++consumed_;
  lock.unlock();
  changed_.notify_all();
  if (slot.error) std::rethrow_exception(slot.error);
  return std::move(slot.frame);
}

}  // namespace vf
