#pragma once
// Record3D's "EXR + JPG" export folder as a FrameSource:
//   metadata.json          same keys as the .r3d metadata (w, h, K, poses, fps, dw, dh)
//   depth/<i>.exr          single-channel float32 depth in metres (read through OpenCV)
//   rgb/<i>.jpg            colour (any size; area-averaged to the depth resolution)
//   conf/<i>.png           optional uint8 confidence 0/1/2
// A flat layout with rgbd/<i>.exr and rgbd/<i>.jpg is accepted too.
#include <memory>
#include <string>

#include "core/frame.h"
#include "io/record3d.h"

namespace vf {

// OpenCV only decodes EXR when OPENCV_IO_ENABLE_OPENEXR is set before its first EXR access; this
// sets it (once, without overriding a user's explicit value).
void enableOpenCvExr();

class Record3dExport : public FrameSource {
 public:
  // Reads metadata.json and the first depth map (for the resolution); throws vf::Error naming the
  // file on any problem.
  explicit Record3dExport(const std::string& folder, Record3dOptions options = {});

  int size() const override { return frame_count_; }
  RgbdFrame load(int index) const override;  // thread-safe
  Intrinsics depthIntrinsics() const override { return depth_intrinsics_; }
  std::string description() const override;
  std::optional<Vec3f> worldUp() const override { return meta_.world_up; }
  // The phone's ARKit poses (record3d.h).
  Trajectory groundTruth() const override { return record3dDevicePoses(meta_, frame_count_); }
  // ARKit's LiDAR depth, as in a .r3d capture (record3d.h).
  std::optional<float> depthNoiseQuadratic() const override { return 0.0005f; }
  const Record3dMetadata& metadata() const { return meta_; }

 private:
  std::string depthPath(int i) const;
  std::string colorPath(int i) const;
  std::string confPath(int i) const;

  std::string folder_;
  Record3dOptions options_;
  Record3dMetadata meta_;
  Intrinsics depth_intrinsics_;
  std::string depth_dir_, color_dir_;  // "depth"/"rgb" or "rgbd"/"rgbd"
  int frame_count_ = 0;
};

// Opens a Record3D capture by its path: a .r3d file, or a folder holding metadata.json (export).
std::unique_ptr<FrameSource> openRecord3d(const std::string& path, Record3dOptions options = {});

}  // namespace vf
