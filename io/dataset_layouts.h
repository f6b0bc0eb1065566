#pragma once
// Folder layouts of public RGB-D datasets, read into a FrameList (io/frame_list_source.h).
// Each has a looksLike...() that checks the files that name the layout (for auto-detection) and
// a read...() that lists the frames, poses, intrinsics and the depth scale.
//
//   7-Scenes / 3DMatch  frame-XXXXXX.{color.jpg|color.png, depth.png, pose.txt},
//                       camera-intrinsics.txt (3x3) here or one folder up (3DMatch keeps it in the
//                       scene above seq-XX); absent: 7-Scenes' documented 585, 585, 320, 240.
//                       Depth in mm, 65535 = no reading; colour not registered to depth.
//   Replica (NICE-SLAM) results/frameXXXXXX.jpg, results/depthXXXXXX.png, traj.txt (a row-major
//                       4x4 per line), cam_params.json here or one folder up (its "scale").
//   ScanNet (exported)  color/N.jpg, depth/N.png (mm), pose/N.txt, intrinsic/intrinsic_depth.txt;
//                       colour is area-resized to the depth size (not registered; an aspect
//                       ratio more than 1 % off the depth's is refused, not stretched).
//   Redwood             color/ (or image/) and depth/ (mm), paired in frame-number order (2.png
//                       before 10.png, io/frame_order.h), one .log trajectory (poses by that
//                       order); intrinsics from camera-intrinsics.json (Open3D) or
//                       PrimeSense's 525, 525, 319.5, 239.5.
// Frames without a timestamp of their own are at the frame index / 30 Hz (the sensors' rate).
// Two files of one frame number ("1.png" beside "01.png") are an error naming both.
#include <optional>
#include <string>

#include "io/frame_list_source.h"
#include "io/tum_dataset.h"

namespace vf {

constexpr double kDatasetFrameRateHz = 30.0;

struct LayoutOptions {
  std::optional<float> depth_units_per_metre;  // overrides the layout's own scale
  std::optional<PinholeOverride> intrinsics;   // overrides the layout's intrinsics
};

bool looksLikeSevenScenes(const std::string& folder);
FrameList readSevenScenes(const std::string& folder, const LayoutOptions& options = {});

bool looksLikeReplica(const std::string& folder);
FrameList readReplica(const std::string& folder, const LayoutOptions& options = {});

bool looksLikeScanNet(const std::string& folder);
FrameList readScanNet(const std::string& folder, const LayoutOptions& options = {});

bool looksLikeRedwood(const std::string& folder);
FrameList readRedwood(const std::string& folder, const LayoutOptions& options = {});

// The layouts' JSON camera files, from their text into the list's camera fields (w/h into
// expected_width/height); `source` names the file in errors, with the field ("camera.fx").
// Replica's cam_params.json {"camera": {"w", "h", "fx", "fy", "cx", "cy", "scale"}}, scale included:
void parseReplicaCamParams(const std::string& text, const std::string& source, FrameList& list);
// Open3D's camera-intrinsics.json {"width", "height", "intrinsic_matrix": 3x3 column-major}:
void parseOpen3dIntrinsics(const std::string& text, const std::string& source, FrameList& list);

// Shared by the layouts: the scale and the intrinsics a FrameList ends with, given the layout's
// own and the overrides.
void applyLayoutOptions(FrameList& list, const LayoutOptions& options);

}  // namespace vf
