#include "app/frame_log.h"

#include <Eigen/Geometry>
#include <cmath>
#include <cstdio>
#include <sstream>

#include "core/text_fields.h"
#include "fusion/lost_reason.h"

namespace vf::app {

std::string csvField(const std::string& text) {
  if (text.find_first_of(",\"\r\n") == std::string::npos) return text;
  std::string quoted = "\"";
  for (char c : text) {
    if (c == '"') quoted += '"';
    quoted += c;
  }
  return quoted + "\"";
}

namespace {

std::string number(const char* format, double value) {
  char text[32];
  std::snprintf(text, sizeof text, format, value);
  return text;
}

// The comma-separated fields of a row, quotes honoured.
std::vector<std::string> splitRow(const std::string& row) {
  std::vector<std::string> fields(1);
  bool quoted = false;
  for (size_t i = 0; i < row.size(); ++i) {
    const char c = row[i];
    if (c == '"' && quoted && i + 1 < row.size() && row[i + 1] == '"') {
      fields.back() += '"';
      ++i;
    } else if (c == '"') {
      quoted = !quoted;
    } else if (c == ',' && !quoted) {
      fields.emplace_back();
    } else {
      fields.back() += c;
    }
  }
  return fields;
}

constexpr size_t kStatusField = 2, kStepField = 11;

// A row whose frame has a pose of its own.
bool tracked(const std::string& status) { return status == "tracked" || status == "map start" || status == "given pose"; }

}  // namespace

void FrameLog::resume(const std::string& csv_text, int first_frame, const Trajectory& done) {
  struct Kept {
    int frame;
    bool tracked, has_step;
  };
  std::vector<Kept> kept;
  std::istringstream lines(csv_text);
  std::string line;
  std::getline(lines, line);  // the header
  while (std::getline(lines, line)) {
    const std::vector<std::string> fields = splitRow(line);
    int frame = 0;
    if (!parseInt(fields[0], frame) || frame < 0 || frame >= first_frame) continue;
    const bool full = fields.size() > kStepField;
    kept.push_back({frame, full && tracked(fields[kStatusField]), full && !fields[kStepField].empty()});
    rows_.push_back(line);
  }
  // Where the rows leave the steps: the last tracked frame's pose is the trajectory's last (a
  // lost frame keeps it), and the step before it the trajectory's last two where that frame's
  // step was one frame long; so the rows after the checkpoint read as the uninterrupted run's.
  for (size_t i = kept.size(); i-- > 0;) {
    if (!kept[i].tracked || done.empty()) continue;
    last_pose_ = done.back().T_world_cam;
    has_last_pose_ = true;
    last_index_ = kept[i].frame;
    const bool one_frame_step = i > 0 && kept[i - 1].tracked && kept[i - 1].frame == last_index_ - 1;
    has_last_step_ = i + 1 == kept.size() && kept[i].has_step && one_frame_step && done.size() >= 2;
    if (has_last_step_) last_step_ = (done[done.size() - 2].T_world_cam.inverse() * last_pose_).translation();
    break;
  }
}

void FrameLog::add(const RgbdFrame& frame, const FrameResult& result) {
  std::string row = std::to_string(frame.index) + "," + number("%.6f", frame.timestamp) + ",";
  const char* status = result.map_start    ? "map start"
                       : result.pose_given ? "given pose"
                       : result.tracked    ? "tracked"
                                           : lostReasonName(result.reason);
  row += csvField(status) + ",";
  row += std::string(result.integrated ? "1" : "0") + ",";
  if (result.map_start || result.pose_given) {  // placed, not matched against anything: no figures of a match
    row += ",,,,,,,";
  } else {
    row += number("%.3f", result.icp_inlier_fraction) + "," + number("%.3f", result.icp_model_coverage) + ",";
    row += number("%.2f", 1000.0 * result.icp_rmse_m) + ",";
    row += std::to_string(result.degenerate_directions) + ",";
    // 1 is "not measured" (FrameResult::weakest_direction_share): blank, not a share.
    row += (result.weakest_direction_share < 1.f ? number("%.4f", result.weakest_direction_share) : "") + ",";
    row += number("%.2f", 100.0 * result.jump_m) + "," + number("%.2f", result.jump_deg) + ",";
  }
  // A frame without a pose of its own (lost: the last good one is kept) has no step; the next
  // tracked frame's step spans the frames lost.
  if (result.tracked && has_last_pose_) {
    const Pose step = last_pose_.inverse() * result.T_world_cam;
    row += number("%.2f", 100.0 * step.translation().norm()) + ",";
    row += number("%.2f", rotationDeg(step)) + ",";
    // Against the step before, where both are one frame apart: a camera's pace changes by
    // millimetres a frame, an alias or a slide by centimetres.
    const bool follows = has_last_step_ && frame.index == last_index_ + 1;
    row += (follows ? number("%.2f", 100.0 * (step.translation() - last_step_).norm()) : "") + ",";
    last_step_ = step.translation();
    has_last_step_ = frame.index == last_index_ + 1;
  } else {
    row += ",,,";
    has_last_step_ = false;
  }
  if (result.tracked) last_pose_ = result.T_world_cam, has_last_pose_ = true, last_index_ = frame.index;
  row += std::to_string(result.integrated ? result.bricks_fused : 0) + ",";
  row += std::to_string(result.integrated ? result.bricks_restarted : 0) + ",";
  if (!result.tracked) {
    row += csvField(result.lost_reason);
  } else if (result.second_start_moved_m > 0.f) {
    row += csvField(std::string("solved again from ") +
                    (result.second_start_at_pace ? "the last second's median pace" : "the motion prior") +
                    ", which fits better: " + number("%.1f", 100.0 * result.second_start_moved_m) +
                    " cm from the first solution");
  }
  rows_.push_back(std::move(row));
}

std::string FrameLog::csv() const {
  std::string out =
      "frame,timestamp,status,fused,matched,on_model,rmse_mm,free_directions,weakest_share,jump_cm,jump_deg,"
      "step_cm,step_deg,step_change_cm,bricks,restarted,note\n";
  for (const std::string& row : rows_) out += row + "\n";
  return out;
}

}  // namespace vf::app
