// Label maps attached to frames: matching, missing files (skip / error), resampling, colour
// files, ids the class table does not name, and class-name resolution.
#include <gtest/gtest.h>

#include <filesystem>
#include <opencv2/imgcodecs.hpp>

#include "core/error.h"
#include "io/image_io.h"
#include "io/labeled_source.h"
#include "test_data.h"

namespace vf {
namespace {

constexpr int kW = 32, kH = 24;

// Frames named f0, f1, ... with constant depth.
class FakeSource : public FrameSource {
 public:
  explicit FakeSource(int n) : n_(n) {}
  int size() const override { return n_; }
  RgbdFrame load(int index) const override {
    RgbdFrame f;
    f.index = index;
    f.name = "f" + std::to_string(index);
    f.depth.resize(kW, kH, 1.f);
    return f;
  }
  Intrinsics depthIntrinsics() const override {
    Intrinsics k;
    k.width = kW, k.height = kH, k.fx = k.fy = 30, k.cx = 16, k.cy = 12;
    return k;
  }
  std::string description() const override { return "fake"; }

 private:
  int n_;
};

ClassTable personTable() {
  ClassTable t;
  t.classes = {{0, "background", {0, 0, 0, 255}}, {1, "person", {255, 0, 0, 255}}};
  return t;
}

LabelImage constantLabels(int w, int h, uint16_t value) {
  LabelImage l(w, h);
  for (int i = 0; i < w * h; ++i) l.data()[i] = value;
  return l;
}

TEST(LabeledSource, MatchesByStemThenByIndex) {
  const std::string dir = test::tempDir("labels_match");
  writeLabelPng(dir + "/f0.png", constantLabels(kW, kH, 1));
  writeLabelPng(dir + "/1.png", constantLabels(kW, kH, 0));  // Record3D-style index name
  LabeledFrameSource source(std::make_unique<FakeSource>(2), dir, personTable(), MissingLabels::Error);
  const RgbdFrame a = source.load(0), b = source.load(1);
  ASSERT_EQ(a.labels.width(), kW);
  EXPECT_EQ(a.labels(5, 5), 1);
  ASSERT_EQ(b.labels.width(), kW);
  EXPECT_EQ(b.labels(5, 5), 0);
  EXPECT_EQ(source.stats().frames_labelled, 2);
}

TEST(LabeledSource, MissingMapIsSkippedAndCountedOrIsAnErrorNamingTheFile) {
  const std::string dir = test::tempDir("labels_missing");
  writeLabelPng(dir + "/f0.png", constantLabels(kW, kH, 1));
  LabeledFrameSource skip(std::make_unique<FakeSource>(3), dir, personTable(), MissingLabels::Skip);
  for (int i = 0; i < 3; ++i) skip.load(i);
  EXPECT_TRUE(skip.load(2).labels.empty());
  const LabelStats stats = skip.stats();
  EXPECT_EQ(stats.frames_labelled, 1);
  ASSERT_EQ(stats.missing_files.size(), 2u);
  EXPECT_EQ(stats.missing_files[0], dir + "/f1.png");

  LabeledFrameSource strict(std::make_unique<FakeSource>(3), dir, personTable(), MissingLabels::Error);
  EXPECT_NO_THROW(strict.load(0));
  try {
    strict.load(1);
    FAIL() << "a missing label map must be an error with --labels-missing error";
  } catch (const Error& e) {
    EXPECT_NE(std::string(e.what()).find(dir + "/f1.png"), std::string::npos) << e.what();
    EXPECT_NE(std::string(e.what()).find("--labels-missing skip"), std::string::npos) << e.what();
  }
}

TEST(LabeledSource, LargerMapIsResampledNearestToDepthResolution) {
  const std::string dir = test::tempDir("labels_resample");
  // 4x the depth resolution (like 720x960 masks for a 192x256 depth map); left half person.
  LabelImage big(4 * kW, 4 * kH);
  for (int y = 0; y < 4 * kH; ++y)
    for (int x = 0; x < 4 * kW; ++x) big(x, y) = x < 2 * kW ? 1 : 0;
  writeLabelPng(dir + "/f0.png", big);
  LabeledFrameSource source(std::make_unique<FakeSource>(1), dir, personTable(), MissingLabels::Error);
  const RgbdFrame f = source.load(0);
  ASSERT_EQ(f.labels.width(), kW);
  ASSERT_EQ(f.labels.height(), kH);
  int person = 0;
  for (int y = 0; y < kH; ++y)
    for (int x = 0; x < kW; ++x) {
      EXPECT_EQ(f.labels(x, y), x < kW / 2 ? 1 : 0) << x << "," << y;
      person += f.labels(x, y) == 1;
    }
  EXPECT_EQ(person, kW * kH / 2);
}

TEST(LabeledSource, ColourMapIsAnErrorNamingTheFile) {
  const std::string dir = test::tempDir("labels_colour");
  cv::Mat rgb(kH, kW, CV_8UC3, cv::Scalar(0, 0, 255));
  ASSERT_TRUE(cv::imwrite(dir + "/f0.png", rgb));
  LabeledFrameSource source(std::make_unique<FakeSource>(1), dir, personTable(), MissingLabels::Skip);
  try {
    source.load(0);
    FAIL() << "a 3-channel label map must be rejected";
  } catch (const Error& e) {
    EXPECT_NE(std::string(e.what()).find(dir + "/f0.png"), std::string::npos) << e.what();
    EXPECT_NE(std::string(e.what()).find("single-channel"), std::string::npos) << e.what();
  }
}

TEST(LabeledSource, IdsMissingFromTheClassTableBecomeUnknownAndAreCounted) {
  const std::string dir = test::tempDir("labels_unknown");
  LabelImage l = constantLabels(kW, kH, 0);
  for (int x = 0; x < 10; ++x) l(x, 0) = 7;
  l(0, 1) = 300;
  writeLabelPng(dir + "/f0.png", l);
  LabeledFrameSource source(std::make_unique<FakeSource>(1), dir, personTable(), MissingLabels::Error);
  const RgbdFrame f = source.load(0);
  EXPECT_EQ(f.labels(3, 0), kUnknownLabel);
  EXPECT_EQ(f.labels(0, 1), kUnknownLabel);
  EXPECT_EQ(f.labels(20, 0), 0);
  const LabelStats stats = source.stats();
  ASSERT_EQ(stats.unknown_id_pixels.size(), 2u);
  EXPECT_EQ(stats.unknown_id_pixels.at(7), 10);
  EXPECT_EQ(stats.unknown_id_pixels.at(300), 1);
}

TEST(ClassList, NamesAndIdsResolveAndUnknownNamesListTheValidOnes) {
  const ClassTable t = personTable();
  EXPECT_EQ(t.resolve({"person"}, "--dynamic-classes"), std::vector<int>({1}));
  EXPECT_EQ(t.resolve({"person, 0,1"}, "--dynamic-classes"), std::vector<int>({1, 0}));
  EXPECT_EQ(t.resolve({"0", " person ", "background"}, "--exclude-classes"), std::vector<int>({0, 1}));
  try {
    t.resolve({"persn"}, "--dynamic-classes");
    FAIL();
  } catch (const Error& e) {
    const std::string m = e.what();
    EXPECT_NE(m.find("--dynamic-classes"), std::string::npos) << m;
    EXPECT_NE(m.find("'persn'"), std::string::npos) << m;
    EXPECT_NE(m.find("background (0), person (1)"), std::string::npos) << m;
  }
  EXPECT_THROW(t.resolve({"5"}, "--dynamic-classes"), Error);
  // Not an id: trailing text, a number past int's range (once std::out_of_range, exit 2).
  EXPECT_THROW(t.resolve({"1x"}, "--dynamic-classes"), Error);
  EXPECT_THROW(t.resolve({"99999999999999999999"}, "--dynamic-classes"), Error);
  EXPECT_THROW(t.resolve({" , "}, "--dynamic-classes"), Error);
  EXPECT_THROW(parseMissingLabels("ignore"), Error);
}

}  // namespace
}  // namespace vf
