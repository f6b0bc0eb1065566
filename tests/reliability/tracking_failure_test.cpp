// Tracking failure on real data (fr3 teddy) must never corrupt the volume: frames dropped from
// the sequence (larger motion), frames whose depth is all zero (sensor dropout) and frames of
// random depth (garbage) are either tracked or reported lost; a lost frame leaves the volume
// untouched; poses stay finite and the trajectory stays within a few cm of ground truth.
#include <gtest/gtest.h>

#include <cmath>
#include <random>

#include "io/trajectory_metrics.h"
#include "io/tum_dataset.h"
#include "reliability/volume_compare.h"
#include "test_data.h"

namespace vf {
namespace {

enum class Damage { None, ZeroDepth, NoiseDepth };

TEST(TrackingFailure, DroppedZeroAndNoiseFramesAreLostNotFusedAndAteStaysSmall) {
  VF_REQUIRE_DATA(folder, "tum_fr3_teddy_head60");
  const TumDataset data(folder);
  ASSERT_EQ(data.size(), 60);
  // Frames 10..39: every third one is left out. Frames 22 and 45 arrive with no depth at all,
  // frames 30 and 50 with uniform noise in 0.3..4 m.
  std::vector<std::pair<int, Damage>> sequence;
  for (int i = 0; i < data.size(); ++i) {
    if (i >= 10 && i < 40 && i % 3 == 2) continue;
    const Damage d = (i == 22 || i == 45) ? Damage::ZeroDepth : (i == 30 || i == 50) ? Damage::NoiseDepth : Damage::None;
    sequence.push_back({i, d});
  }
  Pipeline pipeline(test::teddyParams(3.0f / 256), data.depthIntrinsics(), Device::Cpu);
  std::mt19937 rng(7);
  std::uniform_real_distribution<float> noise(0.3f, 4.f);
  Trajectory estimate;
  int damaged = 0, damaged_lost = 0, intact_lost = 0, with_ground_truth = 0;
  for (const auto& [index, damage] : sequence) {
    RgbdFrame frame = data.load(index);
    for (int p = 0; p < frame.depth.width() * frame.depth.height(); ++p) {
      if (damage == Damage::ZeroDepth) frame.depth.data()[p] = 0.f;
      if (damage == Damage::NoiseDepth) frame.depth.data()[p] = noise(rng);
    }
    const uint64_t before = test::volumeHash(pipeline.hostVolume());
    const FrameResult r = pipeline.processFrame(frame);
    SCOPED_TRACE("frame " + std::to_string(index));
    ASSERT_TRUE(r.T_world_cam.matrix().allFinite());
    if (!r.tracked) {
      EXPECT_FALSE(r.integrated);
      EXPECT_FALSE(r.lost_reason.empty());
      EXPECT_EQ(test::volumeHash(pipeline.hostVolume()), before) << "a lost frame changed the volume";
    }
    if (damage != Damage::None) {
      ++damaged;
      damaged_lost += r.tracked ? 0 : 1;
      // Garbage depth must not be fused: zero depth has nothing to track, noise matches nothing.
      EXPECT_FALSE(r.tracked) << "damaged frame was tracked (" << r.icp_inlier_fraction << " inliers)";
    } else if (!r.tracked) {
      ++intact_lost;
    }
    estimate.push_back({frame.timestamp, r.T_world_cam});
    with_ground_truth += data.groundTruthAt(index) ? 1 : 0;
  }
  EXPECT_EQ(damaged, 4);
  EXPECT_EQ(damaged_lost, 4);
  EXPECT_LE(intact_lost, 2) << "tracking of the intact frames should survive the gaps";
  EXPECT_EQ(pipeline.framesLost(), damaged_lost + intact_lost);

  // Every observed voxel has a weight in 1..max_weight and a TSDF within the truncation.
  const BrickVolumeView v = pipeline.hostVolume();
  size_t observed = 0;
  for (size_t i = 0; i < v.brick_count * kBrickVoxels; ++i) {
    const TsdfVoxel& voxel = v.tsdf[i];
    if (voxel.weight == 0) continue;
    ++observed;
    ASSERT_LE(voxel.weight, pipeline.params().integration.max_weight);
    ASSERT_TRUE(std::isfinite(v.sdfMetres(i)));
  }
  EXPECT_GT(observed, 100000u);

  const AteResult ate = computeAte(estimate, data.groundTruth());
  EXPECT_EQ(ate.pairs, with_ground_truth);
  EXPECT_GT(with_ground_truth, 40);
  EXPECT_LT(ate.rmse_m, 0.03) << "ATE RMSE " << ate.rmse_m << " m";
  EXPECT_LT(ate.max_m, 0.06) << "ATE max " << ate.max_m << " m";
  std::printf("fr3 teddy, %zu frames (%d damaged, %d intact lost): ATE RMSE %.1f mm, max %.1f mm\n", sequence.size(),
              damaged, intact_lost, ate.rmse_m * 1e3, ate.max_m * 1e3);
}

}  // namespace
}  // namespace vf
