#pragma once
// Decodes frames ahead on worker threads so PNG/JPEG/LZFSE decoding overlaps fusion instead of
// stalling it. Frames come out in order; a load error is rethrown by next() for that frame.
//
// One worker suits the CPU backend, whose fusion already keeps every core busy. The GPU fuses a
// 640x480 frame in a millisecond or two, a decoder takes ten (TUM's PNG and JPEG here), so there
// several workers decode frames side by side (FrameSource::load is safe to call from several
// threads at once).
#include <condition_variable>
#include <exception>
#include <map>
#include <mutex>
#include <optional>
#include <thread>
#include <vector>

#include "core/frame.h"
#include "fusion/device.h"

namespace vf {

class FramePrefetcher {
 public:
  static constexpr int kDefaultDepth = 3;
  // Frames first .. first + count - 1; at most `depth` of them (at least one per worker) decoded
  // or being decoded beyond the one next() returns next.
  FramePrefetcher(const FrameSource& source, int first, int count, int depth = kDefaultDepth, int workers = 1);
  ~FramePrefetcher();
  FramePrefetcher(const FramePrefetcher&) = delete;
  FramePrefetcher& operator=(const FramePrefetcher&) = delete;
  // The next frame in order, or nullopt after the last one.
  std::optional<RgbdFrame> next();

  // How many workers to give a pipeline on `device`: one beside the CPU backend, whose fusion
  // keeps every core busy; beside the GPU up to 8, a core left for the pipeline's own thread.
  static int workersFor(Device device);

 private:
  void run();
  struct Slot {
    std::optional<RgbdFrame> frame;
    std::exception_ptr error;
  };
  const FrameSource& source_;
  int next_to_claim_;    // the next frame a worker starts on
  int next_to_deliver_;  // the frame next() returns next
  int end_index_;
  int depth_;
  std::map<int, Slot> ready_;  // decoded, not yet delivered, by frame
  std::mutex mutex_;
  std::condition_variable changed_;
  bool stop_ = false;
  std::vector<std::thread> workers_;
};

}  // namespace vf
