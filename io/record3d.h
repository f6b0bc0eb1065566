#pragma once
// Record3D (iPhone / iPad LiDAR app) captures as a FrameSource.
//
// A .r3d file is a zip: `metadata` (JSON), and per frame i `rgbd/i.jpg` (colour at w x h),
// `rgbd/i.depth` (LZFSE-compressed float32 metres, dw x dh, row-major) and `rgbd/i.conf`
// (LZFSE-compressed uint8 ARKit confidence 0 low / 1 medium / 2 high).
// Metadata keys used: w, h, K (3x3 column-major, for w x h), poses (per frame qx qy qz qw tx ty tz,
// camera-to-world, ARKit camera axes x right / y up / z backward), fps, optional dw, dh,
// frameTimestamps. Captures without dw/dh get them from the size of frame 0's depth map.
// The folder a .r3d unzips to (the same `metadata` and `rgbd/` entries as files) reads the same.
#include <array>
#include <memory>
#include <optional>
#include <string>
#include <vector>

#include "core/frame.h"

namespace vf {

class Record3dEntries;

struct Record3dOptions {
  // Depth pixels whose ARKit confidence is below this (0, 1 or 2) become 0 = no reading.
  int min_confidence = 2;
  bool load_color = true;
  // Depth values per metre: 1 for Record3D's float metres; anything else rescales them.
  float depth_units_per_metre = 1.f;
};

struct Record3dMetadata {
  int rgb_width = 0, rgb_height = 0;      // w, h
  int depth_width = 0, depth_height = 0;  // dw, dh; 0 when the metadata lacks them
  float fx = 0, fy = 0, cx = 0, cy = 0;   // K at the RGB resolution
  double fps = 0;
  std::vector<Pose> T_world_cam;    // per frame, already in the project camera axes
  std::vector<double> timestamps_s;  // frameTimestamps when present, else empty
  std::optional<Vec3f> world_up;     // gravity's up in the poses' frame (ARKit +y via initPose)
};

// Parses the metadata JSON; `source` names the file in error messages.
Record3dMetadata parseRecord3dMetadata(const std::string& json_text, const std::string& source);

// [qx, qy, qz, qw, tx, ty, tz] camera-to-world in ARKit/OpenGL camera axes -> T_world_cam in the
// project's axes (x right, y down, z forward): T_world_glcam * diag(1, -1, -1), world unchanged.
Pose record3dPoseToCamera(const std::array<double, 7>& q_xyzw_t);

// K of the RGB image scaled to a depth map of width x height. Apple scales intrinsics by the
// ratio of image sizes (fx, cx by width ratio; fy, cy by height ratio), and Record3D does the same.
Intrinsics scaleRecord3dIntrinsics(const Record3dMetadata& meta, int width, int height);

// Timestamp of frame `index`: frameTimestamps[index] when present, else index / fps.
double record3dTimestamp(const Record3dMetadata& meta, int index);
// The device's (ARKit's) pose of each of the first `frames` frames at its timestamp; empty when the
// metadata has no pose for every frame.
Trajectory record3dDevicePoses(const Record3dMetadata& meta, int frames);

// The size colour is decoded and fused at: the capture's own RGB size (metadata w x h, 720x960
// on an iPhone: fusion samples it per voxel, so text and book spines stay sharp), or the depth
// size when the metadata states a smaller one.
inline void record3dColorSize(const Record3dMetadata& m, int depth_width, int depth_height, int& width, int& height) {
  const bool larger = m.rgb_width >= depth_width && m.rgb_height >= depth_height;
  width = larger ? m.rgb_width : depth_width;
  height = larger ? m.rgb_height : depth_height;
}

// Throws vf::Error naming `what` and both sizes unless a colour image of width x height is what
// the metadata says (w x h): K is for that size, and a capture without dw/dh has its depth size
// worked out from it, so another size means a wrong camera or depth read with a wrong row stride.
void requireRecord3dColorSize(int width, int height, const Record3dMetadata& meta, const std::string& what);

// Decodes a JPEG/PNG (bytes) of the metadata's RGB size (requireRecord3dColorSize) and
// area-averages it to width x height. The RGB and depth images of a capture cover the same field
// of view (same optical centre once K is scaled), so each depth pixel gets the mean colour of the
// RGB pixels it covers. `what` names the file in errors.
ColorImage decodeColorAtResolution(const std::vector<uint8_t>& encoded, const Record3dMetadata& meta, int width,
                                   int height, const std::string& what);

// Zeroes depth that is not finite or not positive, and where confidence < min_confidence
// (confidence may be null when the capture has none); divides the rest by units_per_metre.
void filterRecord3dDepth(DepthImage& depth_m, const uint8_t* confidence, int min_confidence,
                         float units_per_metre = 1.f);

class Record3dCapture : public FrameSource {
 public:
  // Opens the archive (a .r3d file, or the folder it unzips to) and parses its metadata; throws
  // vf::Error naming the file (and entry) when the archive is not a zip, lacks metadata or a
  // frame entry, or has inconsistent sizes.
  explicit Record3dCapture(const std::string& path, Record3dOptions options = {});
  ~Record3dCapture() override;

  int size() const override { return frame_count_; }
  // Thread-safe: several threads may load different (or the same) indices at once.
  RgbdFrame load(int index) const override;
  Intrinsics depthIntrinsics() const override { return depth_intrinsics_; }
  std::string description() const override;
  std::optional<Vec3f> worldUp() const override { return meta_.world_up; }
  // The phone's ARKit poses: not motion capture, but what a run with --poses icp is compared to
  // (`evaluate --groundtruth capture.r3d`).
  Trajectory groundTruth() const override { return record3dDevicePoses(meta_, frame_count_); }
  // ARKit's LiDAR depth (smoothed by ARKit, 256x192): its error grows far more slowly with
  // distance than a Kinect's. On the shared dance capture (ICP, dancer masked, against ARKit's
  // poses) 0.0005 gave 1.50 cm ATE; 0 2.09, 0.0002 1.82, 0.001 1.95, the Kinect's 0.0019 2.67.
  std::optional<float> depthNoiseQuadratic() const override { return 0.0005f; }

  const Record3dMetadata& metadata() const { return meta_; }
  const std::string& path() const { return path_; }

 private:
  // Reads an LZFSE entry and decodes it into exactly `bytes` bytes at dst.
  void decodeEntryInto(const std::string& entry, uint8_t* dst, size_t bytes) const;
  std::string kind() const;  // "capture" or "capture folder"

  std::string path_;
  Record3dOptions options_;
  std::unique_ptr<Record3dEntries> zip_;  // the zip or the folder
  Record3dMetadata meta_;
  Intrinsics depth_intrinsics_;
  int frame_count_ = 0;
  bool has_confidence_ = false;
};

}  // namespace vf
