// reconstruct --frame-log (app/frame_log.h): a row per frame, steps between tracked frames, the
// tracker's words quoted for CSV, and a resumed run's rows kept.
#include <gtest/gtest.h>

#include <sstream>

#include "app/frame_log.h"

namespace vf::app {
namespace {

std::vector<std::string> lines(const std::string& text) {
  std::vector<std::string> out;
  std::istringstream in(text);
  for (std::string line; std::getline(in, line);) out.push_back(line);
  return out;
}

// The comma-separated fields of a row without quoted commas.
std::vector<std::string> fields(const std::string& row) {
  std::vector<std::string> out;
  std::istringstream in(row);
  for (std::string field; std::getline(in, field, ',');) out.push_back(field);
  if (!row.empty() && row.back() == ',') out.push_back("");
  return out;
}

RgbdFrame frameAt(int index) {
  RgbdFrame frame;
  frame.index = index;
  frame.timestamp = 10.0 + index / 30.0;
  return frame;
}

FrameResult trackedAt(double z_m) {
  FrameResult r;
  r.tracked = true;
  r.integrated = true;
  r.bricks_fused = 100;
  r.icp_inlier_fraction = 0.8f;
  r.icp_model_coverage = 0.9f;
  r.icp_rmse_m = 0.0025f;
  r.T_world_cam = Pose::Identity();
  r.T_world_cam.translation() = Eigen::Vector3d(0, 0, z_m);
  return r;
}

TEST(FrameLog, StepsBetweenTrackedFramesAndLostFramesQuoted) {
  FrameLog log;
  FrameResult start = trackedAt(0.00);
  start.map_start = true;
  start.icp_inlier_fraction = 1.f;  // as the tracker sets it
  log.add(frameAt(0), start);
  log.add(frameAt(1), trackedAt(0.03));
  FrameResult back = trackedAt(0.065);  // 0.5 cm faster than the step before
  back.bricks_restarted = 7;             // and come back to bricks seen long ago
  log.add(frameAt(2), back);
  FrameResult lost = trackedAt(0.5);
  lost.tracked = false;
  lost.integrated = false;
  lost.reason = LostReason::Relocalising;
  lost.lost_reason = "lost; none of 3 candidate poses agrees with the model (best: \"far\")";
  log.add(frameAt(3), lost);
  log.add(frameAt(4), trackedAt(0.125));  // spans the lost frame: no change against one frame's step
  log.add(frameAt(5), trackedAt(0.155));

  const std::vector<std::string> rows = lines(log.csv());
  ASSERT_EQ(rows.size(), 7u);
  const std::vector<std::string> header = fields(rows[0]);
  ASSERT_EQ(header.size(), 17u);
  EXPECT_EQ(header[0], "frame");
  EXPECT_EQ(header[11], "step_cm");
  EXPECT_EQ(header[13], "step_change_cm");
  EXPECT_EQ(header[14], "bricks");
  EXPECT_EQ(header[15], "restarted");
  EXPECT_EQ(header[16], "note");

  const std::vector<std::string> first = fields(rows[1]);
  ASSERT_EQ(first.size(), 17u);
  EXPECT_EQ(first[0], "0");
  EXPECT_EQ(first[2], "map start");
  EXPECT_EQ(first[3], "1");
  for (int f = 4; f <= 10; ++f) EXPECT_EQ(first[size_t(f)], "") << "column " << f;  // placed, not matched
  EXPECT_EQ(first[11], "");  // no frame before it
  EXPECT_EQ(fields(rows[2])[2], "tracked");
  EXPECT_EQ(fields(rows[2])[11], "3.00");
  EXPECT_EQ(fields(rows[2])[13], "");  // the first step has none before it
  const std::vector<std::string> third = fields(rows[3]);
  EXPECT_EQ(third[3], "1");
  EXPECT_EQ(third[4], "0.800");
  EXPECT_EQ(third[6], "2.50");
  EXPECT_EQ(third[8], "");  // the weakest share 1 means "not measured"
  EXPECT_EQ(third[11], "3.50");
  EXPECT_EQ(third[13], "0.50");
  EXPECT_EQ(third[14], "100");
  EXPECT_EQ(third[15], "7");
  EXPECT_EQ(first[15], "0");

  // The lost frame: its status and note quoted (both hold a comma or a quote), no step, no bricks
  // fused or restarted.
  EXPECT_EQ(rows[4].rfind("3,", 0), 0u) << rows[4];
  EXPECT_NE(rows[4].find(",\"lost, relocalising\",0,"), std::string::npos) << rows[4];
  EXPECT_NE(rows[4].find(",,,,0,0,\"lost; none of 3 candidate poses agrees with the model (best: \"\"far\"\")\""),
            std::string::npos)
      << rows[4];

  EXPECT_EQ(fields(rows[5])[11], "6.00");  // from frame 2's pose
  EXPECT_EQ(fields(rows[5])[13], "");
  EXPECT_EQ(fields(rows[6])[11], "3.00");
  EXPECT_EQ(fields(rows[6])[13], "");  // the step before it spanned two frames
}

TEST(FrameLog, AResumedRunReadsAsTheUninterruptedOne) {
  const double z[] = {0.0, 0.03, 0.06, 0.095, 0.12, 0.15};
  FrameLog uninterrupted;
  for (int i = 0; i < 6; ++i) uninterrupted.add(frameAt(i), trackedAt(z[i]));
  // Stopped after frame 2: the checkpoint keeps the poses of frames 0-2.
  Trajectory done;
  for (int i = 0; i < 3; ++i) done.push_back({frameAt(i).timestamp, trackedAt(z[i]).T_world_cam});
  FrameLog interrupted;
  for (int i = 0; i < 3; ++i) interrupted.add(frameAt(i), trackedAt(z[i]));
  FrameLog resumed;
  // Rows past the checkpoint, or not rows at all (a file edited by hand), are not kept.
  resumed.resume(interrupted.csv() + "5,junk past the checkpoint\n-99999999999,x\nnot a row\n", 3, done);
  for (int i = 3; i < 6; ++i) resumed.add(frameAt(i), trackedAt(z[i]));
  EXPECT_EQ(resumed.csv(), uninterrupted.csv());
  EXPECT_EQ(fields(lines(resumed.csv())[4])[13], "0.50");  // frame 3's step against frame 2's
}

TEST(FrameLog, GivenPosesAreNotMatchFigures) {
  FrameLog log;
  for (int i = 0; i < 3; ++i) {
    FrameResult given = trackedAt(0.02 * i);
    given.pose_given = true;
    given.icp_inlier_fraction = given.icp_model_coverage = given.icp_rmse_m = 0.f;  // nothing was matched
    log.add(frameAt(i), given);
  }
  const std::vector<std::string> rows = lines(log.csv());
  ASSERT_EQ(rows.size(), 4u);
  const std::vector<std::string> last = fields(rows[3]);
  EXPECT_EQ(last[2], "given pose");
  for (int f = 4; f <= 10; ++f) EXPECT_EQ(last[size_t(f)], "") << "column " << f;
  EXPECT_EQ(last[11], "2.00");  // the recorded poses still step
  EXPECT_EQ(last[13], "0.00");
}

TEST(FrameLog, CsvFieldsQuoteOnlyWhatNeedsIt) {
  EXPECT_EQ(csvField("tracked"), "tracked");
  EXPECT_EQ(csvField("a, b"), "\"a, b\"");
  EXPECT_EQ(csvField("say \"x\""), "\"say \"\"x\"\"\"");
  EXPECT_EQ(csvField("two\nlines"), "\"two\nlines\"");
}

}  // namespace
}  // namespace vf::app
