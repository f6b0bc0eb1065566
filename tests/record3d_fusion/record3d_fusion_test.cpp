// Fusing the iPhone LiDAR capture: recorded (ARKit) poses build one coherent room, and
// frame-to-model ICP, with the dancer masked out, follows the phone's trajectory.
#include <gtest/gtest.h>

#include <algorithm>
#include <cstdio>

#include "io/frame_list_source.h"
#include "io/trajectory_metrics.h"
#include "r3d_fusion_util.h"
#include "test_data.h"

namespace vf {
namespace {

constexpr int kPerson = 1;

// |predicted depth - measured depth| over pixels with both, outside the person mask grown by
// `margin_px` (the dancer moves between frames).
std::vector<float> depthResiduals(const Prediction& pred, const RgbdFrame& frame, const Pose& T_world_cam,
                                  int margin_px) {
  const Pose T_cam_world = T_world_cam.inverse();
  std::vector<float> out;
  const int w = frame.depth.width(), h = frame.depth.height();
  for (int y = 0; y < h; ++y)
    for (int x = 0; x < w; ++x) {
      const float d = frame.depth(x, y);
      const Vec3f n = pred.normal_world(x, y);
      if (d <= 0.f || (n.x == 0.f && n.y == 0.f && n.z == 0.f)) continue;
      bool person = false;
      for (int v = std::max(0, y - margin_px); v <= std::min(h - 1, y + margin_px) && !person; ++v)
        for (int u = std::max(0, x - margin_px); u <= std::min(w - 1, x + margin_px); ++u)
          if (frame.labels(u, v) == kPerson) person = true;
      if (person) continue;
      const Vec3f pw = pred.vertex_world(x, y);
      const Eigen::Vector3d pc = T_cam_world * Eigen::Vector3d(pw.x, pw.y, pw.z);
      out.push_back(std::abs(float(pc.z()) - d));
    }
  return out;
}

float quantile(std::vector<float> v, double q) {
  if (v.empty()) return 1e9f;
  const size_t k = std::min(v.size() - 1, size_t(q * double(v.size())));
  std::nth_element(v.begin(), v.begin() + long(k), v.end());
  return v[k];
}

TEST(Record3dFusion, GivenPosesFuseOneCoherentRoomThatPredictsHeldOutFrames) {
  VF_REQUIRE_DATA(capture, "record3d_dance_head200.r3d");
  VF_REQUIRE_DATA(labels, "record3d_dance_head200_labels");
  const auto source = test::openDance(capture, labels, labels + "/classes.json");
  Pipeline pipeline(test::roomParams(), source->depthIntrinsics(), Device::Cpu, true);
  pipeline.setDynamicClasses({kPerson});
  // 20 fused frames (even indices 0..38); the odd frames between them are held out.
  for (int i = 0; i < 40; i += 2) {
    const FrameResult r = pipeline.processFrame(source->load(i), PoseSource::Given);
    ASSERT_TRUE(r.integrated) << "frame " << i;
  }
  for (int k : {1, 9, 19, 29, 39}) {
    const RgbdFrame frame = source->load(k);
    const Pose pose = *frame.T_world_cam_given;  // --poses given fuses in the phone's world frame
    const std::vector<float> r = depthResiduals(pipeline.predictFrom(pose, false), frame, pose, 4);
    const float median = quantile(r, 0.5), p90 = quantile(r, 0.9);
    std::printf("held-out frame %d: %zu pixels, median |dz| %.1f mm, 90%% %.1f mm\n", k, r.size(), 1e3f * median,
                1e3f * p90);
    EXPECT_GT(r.size(), 20000u) << "the model should cover most of frame " << k;
    EXPECT_LT(median, 0.02f) << "frame " << k;
    // A doubled wall (poses in the wrong axes or frame) would put a large share of pixels off.
    EXPECT_LT(p90, 0.05f) << "frame " << k;
  }
}

// Mean squared grey-level difference between horizontal and vertical neighbours, over the pixels
// where `use` holds for both: how much fine detail an image holds.
template <class Use>
double gradientEnergy(const ColorImage& image, const Use& use) {
  auto grey = [&](int x, int y) {
    const Rgb8 c = image(x, y);
    return (double(c.r) + double(c.g) + double(c.b)) / 3.0;
  };
  double sum = 0;
  size_t n = 0;
  for (int y = 0; y + 1 < image.height(); ++y)
    for (int x = 0; x + 1 < image.width(); ++x) {
      if (!use(x, y) || !use(x + 1, y) || !use(x, y + 1)) continue;
      const double gx = grey(x + 1, y) - grey(x, y), gy = grey(x, y + 1) - grey(x, y);
      sum += gx * gx + gy * gy;
      ++n;
    }
  return n ? sum / double(n) : 0.0;
}

TEST(Record3dFusion, ColourIsFusedAtTheCamerasOwnResolution) {
  // The capture's colour is 720x960 over 192x256 depth. Fused at full size (each voxel samples
  // the colour pixel it projects to) the model holds more of the frames' detail than fused from
  // colour averaged down to the depth size first, as the reader did before. Both models are
  // rendered at 720x960 from a fused frame's pose and compared with that frame.
  VF_REQUIRE_DATA(capture, "record3d_dance_head200.r3d");
  VF_REQUIRE_DATA(labels, "record3d_dance_head200_labels");
  const auto source = test::openDance(capture, labels, labels + "/classes.json");
  const Intrinsics depth_k = source->depthIntrinsics();
  const RgbdFrame first = source->load(0);
  ASSERT_EQ(first.color.width(), 720);
  ASSERT_EQ(first.color.height(), 960);
  Intrinsics color_k = depth_k;
  const float sx = 720.f / float(depth_k.width), sy = 960.f / float(depth_k.height);
  color_k.fx *= sx, color_k.fy *= sy, color_k.cx = (depth_k.cx + 0.5f) * sx - 0.5f,
      color_k.cy = (depth_k.cy + 0.5f) * sy - 0.5f, color_k.width = 720, color_k.height = 960;

  const PipelineParams params = test::roomParams(0.004f);  // voxels finer than a depth pixel up close
  Pipeline full(params, depth_k, Device::Cpu, true), shrunk(params, depth_k, Device::Cpu, true);
  full.setDynamicClasses({kPerson});
  shrunk.setDynamicClasses({kPerson});
  constexpr int kFrames = 30, kView = 14;
  for (int i = 0; i < kFrames; ++i) {
    RgbdFrame frame = source->load(i);
    ASSERT_TRUE(full.processFrame(frame, PoseSource::Given).integrated);
    frame.color = resizeColorArea(frame.color, depth_k.width, depth_k.height);
    ASSERT_TRUE(shrunk.processFrame(frame, PoseSource::Given).integrated);
  }
  const RgbdFrame view = source->load(kView);
  auto render = [&](Pipeline& fused) {
    const HostBrickVolume bricks = HostBrickVolume::copyOf(fused.hostVolume());
    Pipeline renderer(params, color_k, Device::Cpu, bricks.with_classes);
    renderer.restore(fused.state(), bricks);
    return renderer.predictFrom(*view.T_world_cam_given, true);
  };
  const Prediction a = render(full), b = render(shrunk);
  // Pixels both models see, away from the dancer (who moves): the label map is at depth size.
  auto use = [&](int x, int y) {
    const Vec3f na = a.normal_world(x, y), nb = b.normal_world(x, y);
    const bool seen = (na.x != 0 || na.y != 0 || na.z != 0) && (nb.x != 0 || nb.y != 0 || nb.z != 0);
    return seen && view.labels(int(float(x) / sx), int(float(y) / sy)) != kPerson;
  };
  const double input = gradientEnergy(view.color, use);
  const double sharp = gradientEnergy(a.color, use), soft = gradientEnergy(b.color, use);
  std::printf("colour gradient energy at 720x960, frame %d: input %.1f, fused at full size %.1f, fused from "
              "depth-size colour %.1f\n", kView, input, sharp, soft);
  EXPECT_GT(sharp, 1.3 * soft);
  EXPECT_LT(sharp, input);  // a model averages frames: never sharper than one of them
}

TEST(Record3dFusion, IcpWithPersonMaskedTracksTheFirstThirtyFramesLikeThePhone) {
  VF_REQUIRE_DATA(capture, "record3d_dance_head200.r3d");
  VF_REQUIRE_DATA(labels, "record3d_dance_head200_labels");
  const auto source = test::openDance(capture, labels, labels + "/classes.json");
  Pipeline pipeline(test::roomParams(), source->depthIntrinsics(), Device::Cpu, true);
  pipeline.setDynamicClasses({kPerson});
  Trajectory estimate, phone;
  for (int i = 0; i < 30; ++i) {
    const RgbdFrame frame = source->load(i);
    const FrameResult r = pipeline.processFrame(frame, PoseSource::Icp);
    EXPECT_TRUE(i == 0 || r.tracked) << "frame " << i << ": " << r.lost_reason;
    estimate.push_back({frame.timestamp, r.T_world_cam});
    phone.push_back({frame.timestamp, *frame.T_world_cam_given});
  }
  const AteResult ate = computeAte(estimate, phone);
  // Path length, to put the error in proportion.
  double path = 0;
  for (size_t i = 1; i < phone.size(); ++i)
    path += (phone[i].T_world_cam.translation() - phone[i - 1].T_world_cam.translation()).norm();
  std::printf("ICP vs phone, 30 frames: ATE RMSE %.1f mm, max %.1f mm over a %.2f m path\n", 1e3 * ate.rmse_m,
              1e3 * ate.max_m, path);
  EXPECT_EQ(ate.pairs, 30);
  EXPECT_LT(ate.rmse_m, 0.03);
}

}  // namespace
}  // namespace vf
