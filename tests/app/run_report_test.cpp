// Issue 37: the progress line's clock and estimate, and the share of depth beyond the fusion range.
#include <gtest/gtest.h>

#include "app/depth_range_tally.h"
#include "app/progress.h"

namespace vf::app {
namespace {

TEST(ClockDuration, ReadsLikeAClock) {
  EXPECT_EQ(clockDuration(0), "0:00");
  EXPECT_EQ(clockDuration(41.4), "0:41");
  EXPECT_EQ(clockDuration(725), "12:05");
  EXPECT_EQ(clockDuration(3729), "1:02:09");
}

TEST(EstimatedTimeLeft, ExtrapolatesTheRateOnceItMeansSomething) {
  EXPECT_EQ(estimatedTimeLeft(376, 626, 40.9), "0:27");  // 9.2 frames/s, 250 frames to go
  EXPECT_EQ(estimatedTimeLeft(1, 626, 0.5), "");          // too early: start-up costs
  EXPECT_EQ(estimatedTimeLeft(5, 1000, 3.0), "");         // under 2 % done
  EXPECT_EQ(estimatedTimeLeft(626, 626, 68.0), "");       // nothing left
}

// A depth image whose readings are `near` in its left part and `far` in the rest.
DepthImage splitDepth(int width, int height, int near_columns, float near, float far) {
  DepthImage depth(width, height, 0.f);
  for (int y = 0; y < height; ++y)
    for (int x = 0; x < width; ++x) depth(x, y) = x < near_columns ? near : far;
  return depth;
}

TEST(DepthRangeTally, CountsTheShareBeyondTheRangeAndSuggestsOne) {
  DepthRangeTally tally(0.2f, 4.0f);
  tally.add(splitDepth(64, 48, 48, 2.0f, 6.1f));  // a quarter of the readings at 6.1 m
  DepthImage holes(64, 48, 0.f);                   // no reading counts as neither
  holes(10, 10) = std::numeric_limits<float>::quiet_NaN();
  holes(12, 12) = 0.1f;                            // nearer than the sensor's minimum
  tally.add(holes);
  EXPECT_EQ(tally.validReadings(), 32 * 24);
  EXPECT_NEAR(tally.beyondShare(), 0.25, 1e-9);
  EXPECT_FLOAT_EQ(tally.rangeKeeping(0.99), 6.25f);  // the quarter-metre bin holding 6.1 m
  const std::string line = tally.report();
  EXPECT_NE(line.find("25.0 % of the valid readings lie beyond --max-depth-m 4.0 m"), std::string::npos) << line;
  EXPECT_NE(line.find("--max-depth-m 6.2 would fuse 99 %"), std::string::npos) << line;
}

TEST(DepthRangeTally, SaysNothingWhenNothingWasDroppedAndSuggestsOnlyWhenItMatters) {
  DepthRangeTally within(0.2f, 4.0f);
  within.add(splitDepth(64, 48, 64, 2.0f, 0.f));
  EXPECT_EQ(within.report(), "");
  DepthRangeTally few(0.2f, 4.0f);
  few.add(splitDepth(200, 2, 198, 2.0f, 5.0f));  // column 198 of the counted even ones: 1 of 100
  const std::string line = few.report();
  EXPECT_NE(line.find("1.0 % of the valid readings"), std::string::npos) << line;
  EXPECT_EQ(line.find("would fuse"), std::string::npos) << line;
  DepthRangeTally stray(0.2f, 4.0f);
  stray.add(splitDepth(4000, 2, 3998, 2.0f, 5.0f));  // 1 of 2000: no news
  EXPECT_EQ(stray.beyondRange(), 1);
  EXPECT_EQ(stray.report(), "");
}

}  // namespace
}  // namespace vf::app
