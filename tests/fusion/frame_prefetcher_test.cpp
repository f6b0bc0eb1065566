// FramePrefetcher: frames come out in order whatever the number of workers, a frame that fails
// to load rethrows its error at its turn (and the frames after it still come), and several
// workers really decode side by side (what the GPU backend needs: decoding, not fusion, is its
// bottleneck).
#include <gtest/gtest.h>

#include <atomic>
#include <chrono>
#include <condition_variable>
#include <mutex>
#include <string>
#include <thread>

#include "core/error.h"
#include "fusion/frame_prefetcher.h"

namespace vf {
namespace {

// Frame i has timestamp i; load(fail_at) throws; the first `meet` loads each wait until that many
// loads are in progress at once (or give up after a few seconds and say so).
class CountingSource : public FrameSource {
 public:
  CountingSource(int frames, int fail_at, int meet) : frames_(frames), fail_at_(fail_at), meet_(meet) {}
  int size() const override { return frames_; }
  RgbdFrame load(int index) const override {
    {
      std::unique_lock<std::mutex> lock(mutex_);
      const int now = ++in_flight_;
      most_at_once_ = std::max(most_at_once_, now);
      if (index < meet_) {
        changed_.notify_all();
        if (!changed_.wait_for(lock, std::chrono::seconds(5), [&] { return most_at_once_ >= meet_; }))
          met_ = false;
      }
      --in_flight_;
    }
    // Later frames finish out of order: the even ones take a little longer.
    if (index >= meet_ && index % 2 == 0) std::this_thread::sleep_for(std::chrono::milliseconds(2));
    if (index == fail_at_) throw Error("frame " + std::to_string(index) + " cannot be read");
    RgbdFrame frame;
    frame.timestamp = index;
    frame.name = std::to_string(index);
    return frame;
  }
  Intrinsics depthIntrinsics() const override { return {}; }
  std::string description() const override { return "counting source"; }
  int mostAtOnce() const {
    std::lock_guard<std::mutex> lock(mutex_);
    return most_at_once_;
  }
  bool met() const {
    std::lock_guard<std::mutex> lock(mutex_);
    return met_;
  }

 private:
  int frames_, fail_at_, meet_;
  mutable std::mutex mutex_;
  mutable std::condition_variable changed_;
  mutable int in_flight_ = 0, most_at_once_ = 0;
  mutable bool met_ = true;
};

TEST(FramePrefetcher, FramesComeOutInOrderAndAFailedOneRethrowsAtItsTurn) {
  for (int workers : {1, 4}) {
    const CountingSource source(40, 17, 0);
    FramePrefetcher prefetcher(source, 5, 30, 3, workers);
    for (int i = 5; i < 35; ++i) {
      if (i == 17) {
        EXPECT_THROW(prefetcher.next(), Error) << workers << " workers";
        continue;
      }
      const std::optional<RgbdFrame> frame = prefetcher.next();
      ASSERT_TRUE(frame.has_value()) << workers << " workers, frame " << i;
      EXPECT_EQ(frame->timestamp, double(i)) << workers << " workers";
    }
    EXPECT_FALSE(prefetcher.next().has_value());
    if (workers == 1) {
      EXPECT_EQ(source.mostAtOnce(), 1);
    }
  }
}

TEST(FramePrefetcher, FourWorkersDecodeFourFramesAtOnce) {
  const CountingSource source(12, -1, 4);
  FramePrefetcher prefetcher(source, 0, 12, 4, 4);
  for (int i = 0; i < 12; ++i) ASSERT_EQ(prefetcher.next()->timestamp, double(i));
  EXPECT_TRUE(source.met()) << "the first four frames were not decoded side by side";
  EXPECT_EQ(source.mostAtOnce(), 4);  // never more than asked for
}

TEST(FramePrefetcher, StoppingEarlyAndEmptyRangesDoNotHang) {
  const CountingSource source(100, -1, 0);
  {
    FramePrefetcher prefetcher(source, 0, 100, 8, 4);
    ASSERT_TRUE(prefetcher.next().has_value());
  }  // destroyed with workers mid-way
  FramePrefetcher none(source, 0, 0, 3, 4);
  EXPECT_FALSE(none.next().has_value());
}

// One decoder beside the CPU backend (its fusion uses every core), several beside the GPU.
TEST(FramePrefetcher, TheGpuGetsMoreDecodersThanTheCpu) {
  EXPECT_EQ(FramePrefetcher::workersFor(Device::Cpu), 1);
  const int gpu = FramePrefetcher::workersFor(Device::Cuda);
  EXPECT_GE(gpu, 1);
  EXPECT_LE(gpu, 8);
  if (std::thread::hardware_concurrency() >= 3) {
    EXPECT_GE(gpu, 2);
  }
}

}  // namespace
}  // namespace vf
