#pragma once
// Point features with depth, for poses between views far apart (relocalisation after a gap,
// loop closure): ORB keypoints (Rublee et al. 2011, OpenCV) on the grey image, each lifted to 3D
// by the depth under it, matched by descriptor and turned into a rigid motion by RANSAC over
// 3-point alignments (Horn/Umeyama), then refit on the inliers; or, where only one side's depth
// can be trusted, by RANSAC over perspective-n-point solutions (EPnP, OpenCV calib3d).
#include <cstdint>
#include <optional>
#include <vector>

#include "core/frame.h"
#include "core/intrinsics.h"
#include "core/pose.h"

namespace vf::slam {

struct FrameFeatures {
  static constexpr int kDescriptorBytes = 32;
  std::vector<Vec3f> points_cam;         // camera frame, metres
  std::vector<uint8_t> descriptors;      // kDescriptorBytes each, in the order of points_cam
  int size() const { return int(points_cam.size()); }
  bool empty() const { return points_cam.empty(); }
};

// Keypoints of the frame's colour (empty when it has none) that have depth within the range.
FrameFeatures extractFeatures(const RgbdFrame& frame, const Intrinsics& depth_camera, float min_depth_m,
                              float max_depth_m);

struct RelativePose {
  Pose T_target_source = Pose::Identity();  // maps the source frame's points into the target's
  int matches = 0;                          // descriptor matches tried
  int inliers = 0;                          // matches the motion explains
};

// The motion that brings `source`'s points onto `target`'s, when enough matches agree on one
// (at least min_inliers); nullopt otherwise.
std::optional<RelativePose> estimateRelativePose(const FrameFeatures& source, const FrameFeatures& target,
                                                 int min_inliers = 15);

// The same motion from the target's 3D points and the source's pixels alone (perspective-n-point,
// EPnP in RANSAC): it needs no depth at the source's keypoints, which matters where colour and
// depth come from two sensors (7-Scenes: a keypoint on an edge often takes the depth behind it).
// depth_camera: the camera both sets of points were lifted with.
std::optional<RelativePose> estimateRelativePoseFromPixels(const FrameFeatures& source, const FrameFeatures& target,
                                                           const Intrinsics& depth_camera, int min_inliers = 10);

}  // namespace vf::slam
