#include "app/reconstruct_report.h"

#include "app/progress.h"

#include <sys/resource.h>

#include <algorithm>
#include <cstdio>
#include <map>
#include <string>

namespace vf::app {

double peakResidentMiB() {
  rusage usage{};
  getrusage(RUSAGE_SELF, &usage);
  return double(usage.ru_maxrss) / 1024.0;  // ru_maxrss is in KiB on Linux
}

void printTrackingSummary(int frames, const std::vector<LostFrame>& lost, int frames_fused, int relocalisations) {
  std::printf("tracked %d of %d frames, fused %d", frames - int(lost.size()), frames, frames_fused);
  if (relocalisations > 0) std::printf(", relocalised %d time%s", relocalisations, relocalisations == 1 ? "" : "s");
  if (lost.empty()) {
    std::printf("\n");
    return;
  }
  // Per reason: how many, and the first few frames with the first one's details.
  std::printf("; %zu without a pose (not fused, left out of the trajectory):\n", lost.size());
  std::map<LostReason, std::vector<const LostFrame*>> by_reason;
  for (const LostFrame& l : lost) by_reason[l.reason].push_back(&l);
  for (const auto& [reason, frames_lost] : by_reason) {
    std::printf("  %4zu  %s:", frames_lost.size(), lostReasonName(reason));
    const size_t shown = std::min<size_t>(frames_lost.size(), 6);
    for (size_t i = 0; i < shown; ++i) std::printf(" %s", frames_lost[i]->name.c_str());
    if (shown < frames_lost.size()) std::printf(" ...");
    std::printf(" (%s: %s)\n", frames_lost[0]->name.c_str(), frames_lost[0]->why.c_str());
  }
}

namespace {

std::vector<const slam::PriorHeldStretch*> reportedPriorHeld(const std::vector<slam::PriorHeldStretch>& stretches) {
  std::vector<const slam::PriorHeldStretch*> long_ones;
  for (const slam::PriorHeldStretch& s : stretches)
    if (s.frames() >= kPriorHeldReportFrames) long_ones.push_back(&s);
  return long_ones;
}

}  // namespace

int priorHeldFrames(const std::vector<slam::PriorHeldStretch>& stretches) {
  int frames = 0;
  for (const slam::PriorHeldStretch* s : reportedPriorHeld(stretches)) frames += s->frames();
  return frames;
}

void printPriorHeld(const std::vector<slam::PriorHeldStretch>& stretches) {
  const std::vector<const slam::PriorHeldStretch*> long_ones = reportedPriorHeld(stretches);
  if (long_ones.empty()) return;
  int frames = 0, most = 0;
  for (const slam::PriorHeldStretch* s : long_ones) {
    frames += s->frames();
    most = std::max(most, s->directions);
  }
  const std::string unmeasured = most == 1 ? "a direction" : "up to " + std::to_string(most) + " directions";
  std::printf("motion prior: for %d frames in %zu stretch%s the view left %s unmeasured (one wall, a corridor along "
              "its length) and the camera's own motion carried %s; poses there can have drifted unseen:",
              frames, long_ones.size(), long_ones.size() == 1 ? "" : "es", unmeasured.c_str(), most == 1 ? "it" : "them");
  const size_t shown = std::min<size_t>(long_ones.size(), 5);
  for (size_t i = 0; i < shown; ++i)
    std::printf("%s %s to %s (%d frames)", i == 0 ? "" : ",", long_ones[i]->first_name.c_str(),
                long_ones[i]->last_name.c_str(), long_ones[i]->frames());
  std::printf("%s\n", shown < long_ones.size() ? ", ..." : "");
}

void printLoopClosure(const slam::GlobalReport& r, bool enabled) {
  if (!enabled) {
    std::printf("loop closure: off (--loop-closure on finds where the camera came back and fuses again)\n");
    return;
  }
  std::printf("loop closure: %d keyframes, %d candidate pairs checked, %d loops found, %d hold (%d rejected)", r.keyframes,
              r.candidates, r.loops_found, r.loops_accepted, r.loops_found - r.loops_accepted);
  if (r.maps > 1) {
    std::printf("; tracking started %d new map%s where it was lost and could not find its map again", r.maps - 1,
                r.maps == 2 ? "" : "s");
    if (r.maps_turned > 0)
      std::printf(" (%d also searched for turned to face as the older maps' floor and walls do)", r.maps_turned);
    if (r.maps_joined == r.maps - 1)
      std::printf(", %s joined to the older maps by loops", r.maps == 2 ? "it" : "all");
    else
      std::printf(", %d joined to the older maps by loops, %d placed only where the camera's walk led", r.maps_joined,
                  r.maps - 1 - r.maps_joined);
  }
  if (r.moved()) {
    std::printf("; frames moved up to %.2f cm (median %.2f cm), fused again at the optimised poses\n",
                100.0 * r.largest_correction_m, 100.0 * r.median_correction_m);
    return;
  }
  if (r.maps > 1) {
    std::printf("; every map fused again into one scene\n");
    return;
  }
  const char* stand = r.bricks_restarted > 0 ? "stand" : "and scene stand";
  if (r.loops_accepted > 0 && r.largest_correction_m > 0)
    std::printf("; they move no frame's view by more than %.2f cm: the first pass's poses %s", 100.0 * r.largest_correction_m,
                stand);
  else if (r.loops_accepted > 0)
    std::printf("; they agree with the first pass's poses within their noise: its poses %s", stand);
  else
    std::printf("; the first pass's poses %s", stand);
  if (r.bricks_restarted > 0)
    std::printf(", and every frame is fused again at them: tracking restarted %lld bricks where the camera came back "
                "after its model's window, and the scene keeps every visit",
                static_cast<long long>(r.bricks_restarted));
  std::printf("\n");
}

void printLabelSummary(const LabelStats& stats, const ClassTable& classes, int frames) {
  std::printf("labels: %d of %d frames labelled", stats.frames_labelled, frames);
  if (!stats.missing_files.empty()) {
    std::printf("; %zu without a label map (fused without labels):", stats.missing_files.size());
    const size_t shown = std::min<size_t>(stats.missing_files.size(), 5);
    for (size_t i = 0; i < shown; ++i) std::printf(" %s", stats.missing_files[i].c_str());
    if (shown < stats.missing_files.size()) std::printf(" ...");
  }
  std::printf("\n");
  if (!stats.unknown_id_pixels.empty()) {
    std::printf("labels: ids not in the class table (%zu classes named) were fused as unknown:",
                classes.classes.size());
    for (const auto& [id, pixels] : stats.unknown_id_pixels) std::printf(" %d (%lld px)", id, pixels);
    std::printf("\n");
  }
}

void printTimingTable(const StageTimer& timer, int frames, double wall_s, std::vector<int> bricks_per_frame,
                      bool stage_table) {
  if (!stage_table) {
    char seconds[32];
    std::snprintf(seconds, sizeof seconds, "%.1f s", wall_s);
    const std::string took = wall_s < 60 ? seconds : clockDuration(wall_s);
    std::printf("\n%d frames in %s (%.1f frames/s including I/O)\n", frames, took.c_str(),
                wall_s > 0 ? frames / wall_s : 0.0);
    return;
  }
  std::printf("\n%-12s %10s %10s %10s\n", "stage", "median ms", "mean ms", "total s");
  double sum_median = 0;
  for (const std::string& stage : timer.stages()) {
    std::printf("%-12s %10.2f %10.2f %10.2f\n", stage.c_str(), timer.median(stage), timer.mean(stage),
                timer.total(stage) / 1000.0);
    if (stage == "measure" || stage == "track" || stage == "integrate" || stage == "raycast")
      sum_median += timer.median(stage);
  }
  std::printf("%-12s %10.2f   -> %.1f frames/s from the four stages' medians\n", "fusion", sum_median,
              sum_median > 0 ? 1000.0 / sum_median : 0.0);
  std::printf("%d frames in %.2f s (%.1f frames/s including I/O)\n", frames, wall_s, wall_s > 0 ? frames / wall_s : 0.0);
  if (bricks_per_frame.empty()) return;
  // What integrate and raycast cost follows: the surface in view, not the scene's extent.
  std::sort(bricks_per_frame.begin(), bricks_per_frame.end());
  std::printf("bricks fused per frame: median %d, largest %d\n", bricks_per_frame[bricks_per_frame.size() / 2],
              bricks_per_frame.back());
}

namespace {

// The strings here are the run's own (reason names, device names); escaped all the same.
std::string jsonString(const std::string& text) {
  std::string out = "\"";
  for (const char c : text) {
    if (c == '"' || c == '\\') out += '\\';
    if (static_cast<unsigned char>(c) < 0x20) {
      char code[8];
      std::snprintf(code, sizeof code, "\\u%04x", c);
      out += code;
    } else {
      out += c;
    }
  }
  return out + "\"";
}

}  // namespace

std::string runFiguresJson(const RunFigures& f) {
  std::map<std::string, int> by_reason;
  for (const LostFrame& l : f.lost) ++by_reason[lostReasonName(l.reason)];
  std::string reasons;
  for (const auto& [name, count] : by_reason)
    reasons += (reasons.empty() ? "" : ", ") + jsonString(name) + ": " + std::to_string(count);
  char numbers[512];
  std::snprintf(numbers, sizeof numbers,
                "\"frames\": %d, \"tracked\": %d, \"fused\": %d, \"lost\": %zu, \"relocalisations\": %d, \"maps\": %d, "
                "\"prior_held_frames\": %d, \"passes\": %d, \"bricks_restarted\": %lld, "
                "\"resumed_after_frame\": %d, \"seconds\": %.3f, \"peak_mib\": %.1f, \"bricks\": %d, "
                "\"active_voxels\": %zu",
                f.frames, f.frames - int(f.lost.size()), f.fused, f.lost.size(), f.relocalisations, f.maps,
                f.prior_held_frames, f.passes, static_cast<long long>(f.bricks_restarted), f.resumed_after_frame,
                f.seconds, peakResidentMiB(), f.bricks, f.active_voxels);
  return std::string("{") + numbers + ", \"device\": " + jsonString(f.device) + ", \"lost_by_reason\": {" + reasons +
         "}}\n";
}

void printMemory(int bricks, size_t volume_bytes) {
  std::printf("volume: %d bricks (%.1f M voxels), %.0f MiB; peak memory %.0f MiB\n", bricks,
              double(bricks) * kBrickVoxels / 1e6, double(volume_bytes) / double(1 << 20), peakResidentMiB());
}

}  // namespace vf::app
