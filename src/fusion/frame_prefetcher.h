#pragma once
// Decodes frames ahead on a worker thread so PNG/JPEG/LZFSE decoding overlaps fusion instead of
// stalling it. Frames come out in order; a load error is rethrown by next() for that frame.
#include <condition_variable>
#include <deque>
#include <exception>
#include <mutex>
#include <optional>
#include <thread>

#include "core/frame.h"

namespace vf {

class FramePrefetcher {
 public:
  FramePrefetcher(const FrameSource& source, int first, int count, int depth = 3);
  ~FramePrefetcher();
  // The next frame in order, or nullopt after the last one.
  std::optional<RgbdFrame> next();

 private:
  void run();
  struct Slot {
    std::optional<RgbdFrame> frame;
    std::exception_ptr error;
  };
  const FrameSource& source_;
  int next_index_, end_index_;
  size_t depth_;
  std::deque<Slot> ready_;
  std::mutex mutex_;
  std::condition_variable changed_;
  bool stop_ = false;
  int consumed_ = 0, total_;
  std::thread worker_;
};

}  // namespace vf
