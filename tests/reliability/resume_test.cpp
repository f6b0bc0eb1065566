// Checkpoint and resume (fusion/checkpoint.h, slam/reconstruction.h) on real data, CPU backend:
// a run stopped after frame k and resumed from its checkpoint ends with the same volume, voxel
// for voxel, and the same poses, bit for bit, as a run that never stopped. Runs must also be
// deterministic.
#include <gtest/gtest.h>

#include <filesystem>
#include <functional>
#include <fstream>
#include <iterator>

#include "core/error.h"
#include "fusion/checkpoint.h"
#include "slam/reconstruction.h"
#include "io/tum_dataset.h"
#include "reliability/volume_compare.h"
#include "test_data.h"

namespace vf {
namespace {

constexpr int kFrames = 14;

std::vector<Pose> fuse(Pipeline& p, const TumDataset& data, int first, int end) {
  std::vector<Pose> poses;
  for (int i = first; i < end; ++i) {
    const FrameResult r = p.processFrame(data.load(i));
    poses.push_back(r.T_world_cam);
  }
  return poses;
}

// Teddy's first 40 frames with every loop taken as a correction (loops 15 frames apart, none
// agreeing, any move re-fused), so that a run always reaches its second pass.
ReconstructionOptions secondPassOptions(const std::string& dataset) {
  ReconstructionOptions options;
  options.params = test::teddyParams();
  options.device = Device::Cpu;
  options.max_frames = 40;
  options.settings = {{"dataset", dataset}};
  options.global.loops.min_separation_frames = 15;
  options.global.loops_agree_chi = 0;
  options.global.min_correction_m = 0;
  return options;
}

class ResumeTest : public ::testing::Test {
 protected:
  void SetUp() override {
    VF_REQUIRE_DATA(folder, "tum_fr3_teddy_head60");
    data_ = std::make_unique<TumDataset>(folder);
    dir_ = test::tempDir("resume");
  }
  std::unique_ptr<TumDataset> data_;
  std::string dir_;
};

TEST_F(ResumeTest, CpuRunsAreBitIdentical) {
  Pipeline a(test::teddyParams(), data_->depthIntrinsics(), Device::Cpu);
  Pipeline b(test::teddyParams(), data_->depthIntrinsics(), Device::Cpu);
  const std::vector<Pose> pa = fuse(a, *data_, 0, kFrames);
  const std::vector<Pose> pb = fuse(b, *data_, 0, kFrames);
  for (int i = 0; i < kFrames; ++i) EXPECT_TRUE(test::sameBits(pa[size_t(i)], pb[size_t(i)])) << "frame " << i;
  EXPECT_EQ(test::firstDifferentBrick(a.hostVolume(), b.hostVolume()), -1);
}

TEST_F(ResumeTest, ResumedRunEqualsUninterruptedRun) {
  Pipeline full(test::teddyParams(), data_->depthIntrinsics(), Device::Cpu);
  const std::vector<Pose> reference = fuse(full, *data_, 0, kFrames);
  ASSERT_EQ(full.framesLost(), 0);
  // Stop at several points, including right after the first frame (world = first camera).
  for (int stop : {1, 5, 9}) {
    SCOPED_TRACE("stopped after frame " + std::to_string(stop));
    const std::string path = dir_ + "/run.checkpoint";
    std::vector<Pose> poses;
    {
      Pipeline first(test::teddyParams(), data_->depthIntrinsics(), Device::Cpu);
      poses = fuse(first, *data_, 0, stop);
      RunProgress progress;
      progress.settings = {{"dataset", "teddy"}, {"note", "line 1\nline 2"}};
      progress.frames_done = stop;
      // Frame 3 is reported lost (as if tracking had rejected it): it has no pose.
      for (int i = 0; i < stop; ++i)
        if (i != 3) progress.trajectory.push_back({0.5 * i, poses[size_t(i)]});
      if (stop > 3) progress.lost = {LostFrame{3, "frame-3", LostReason::FewInliers, "a reason"}};
      progress.session = {1, 2, 3};
      writeCheckpoint(path, first, progress);
    }
    Pipeline resumed(test::teddyParams(), data_->depthIntrinsics(), Device::Cpu);
    const RunProgress saved = readCheckpoint(path, resumed, {{"dataset", "teddy"}});
    EXPECT_EQ(saved.settings.size(), 2u);
    EXPECT_EQ(saved.settings[1].second, "line 1\nline 2");
    ASSERT_EQ(saved.trajectory.size(), size_t(stop > 3 ? stop - 1 : stop));
    EXPECT_TRUE(test::sameBits(saved.trajectory.back().T_world_cam, poses.back()));
    EXPECT_EQ(saved.trajectory.back().timestamp, 0.5 * (stop - 1));
    ASSERT_EQ(saved.lost.size(), stop > 3 ? 1u : 0u);
    if (stop > 3) {
      EXPECT_EQ(saved.lost[0].index, 3);
      EXPECT_EQ(saved.lost[0].name, "frame-3");
      EXPECT_EQ(saved.lost[0].reason, LostReason::FewInliers);
      EXPECT_EQ(saved.lost[0].why, "a reason");
    }
    EXPECT_EQ(saved.session, (std::vector<uint8_t>{1, 2, 3}));
    EXPECT_EQ(resumed.framesProcessed(), stop);
    const std::vector<Pose> rest = fuse(resumed, *data_, stop, kFrames);
    poses.insert(poses.end(), rest.begin(), rest.end());
    ASSERT_EQ(poses.size(), reference.size());
    for (int i = 0; i < kFrames; ++i)
      EXPECT_TRUE(test::sameBits(poses[size_t(i)], reference[size_t(i)])) << "frame " << i;
    EXPECT_EQ(resumed.framesLost(), full.framesLost());
    EXPECT_EQ(test::firstDifferentBrick(resumed.hostVolume(), full.hostVolume()), -1);
    EXPECT_GT(full.brickCount(), 100);
  }
}

TEST_F(ResumeTest, AReconstructionStoppedAndResumedEndsAsOneThatRanThrough) {
  ReconstructionOptions options;
  options.params = test::teddyParams();
  options.device = Device::Cpu;
  options.max_frames = kFrames;
  options.settings = {{"dataset", "teddy"}};
  Reconstruction through(*data_, options);
  ASSERT_EQ(through.run({}), Reconstruction::Outcome::Finished);
  const std::string path = dir_ + "/stopped.checkpoint";
  {
    Reconstruction stopped(*data_, options);
    Reconstruction::Callbacks callbacks;
    int frames_seen = 0;
    callbacks.on_frame = [&](const RgbdFrame&, const FrameResult&) { ++frames_seen; };
    callbacks.should_stop = [&] { return stopped.framesDone() == 6; };
    ASSERT_EQ(stopped.run(callbacks), Reconstruction::Outcome::Stopped);
    EXPECT_EQ(frames_seen, 6);
    stopped.saveCheckpoint(path);
  }
  Reconstruction resumed(*data_, options);
  resumed.resume(path);
  EXPECT_EQ(resumed.framesDone(), 6);
  ASSERT_EQ(resumed.run({}), Reconstruction::Outcome::Finished);
  ASSERT_EQ(resumed.trajectory().size(), through.trajectory().size());
  for (size_t i = 0; i < through.trajectory().size(); ++i)
    EXPECT_TRUE(test::sameBits(resumed.trajectory()[i].T_world_cam, through.trajectory()[i].T_world_cam)) << i;
  EXPECT_EQ(test::firstDifferentBrick(resumed.pipeline().hostVolume(), through.pipeline().hostVolume()), -1);
  // Other settings: the checkpoint is not continued.
  options.settings = {{"dataset", "another"}};
  Reconstruction other(*data_, options);
  EXPECT_NE(test::errorOf([&] { other.resume(path); }).find("dataset = teddy, this run has dataset = another"),
            std::string::npos);
}

// A run stopped in its second pass (fusion again at the optimised poses) and resumed ends as one
// that ran through, voxel for voxel and pose for pose. The loop closure is told to act on what
// it finds in the teddy's 40 frames (its defaults leave such agreeing loops alone).
TEST_F(ResumeTest, ARunStoppedInItsSecondPassResumesToTheSameScene) {
  const ReconstructionOptions options = secondPassOptions("teddy");
  Reconstruction through(*data_, options);
  ASSERT_EQ(through.run({}), Reconstruction::Outcome::Finished);
  ASSERT_EQ(through.pass(), 2) << "no loop moved the poses: the second pass was not reached";
  ASSERT_GT(through.globalReport().loops_accepted, 0);
  const std::string path = dir_ + "/second_pass.checkpoint";
  {
    Reconstruction stopped(*data_, options);
    Reconstruction::Callbacks callbacks;
    callbacks.should_stop = [&] { return stopped.pass() == 2 && stopped.framesDone() == 17; };
    ASSERT_EQ(stopped.run(callbacks), Reconstruction::Outcome::Stopped);
    stopped.saveCheckpoint(path);
  }
  Reconstruction resumed(*data_, options);
  resumed.resume(path);
  EXPECT_EQ(resumed.pass(), 2);
  EXPECT_EQ(resumed.framesDone(), 17);
  ASSERT_EQ(resumed.run({}), Reconstruction::Outcome::Finished);
  ASSERT_EQ(resumed.trajectory().size(), through.trajectory().size());
  for (size_t i = 0; i < through.trajectory().size(); ++i)
    EXPECT_TRUE(test::sameBits(resumed.trajectory()[i].T_world_cam, through.trajectory()[i].T_world_cam)) << i;
  ASSERT_EQ(resumed.odometry().size(), through.odometry().size());
  EXPECT_EQ(test::firstDifferentBrick(resumed.pipeline().hostVolume(), through.pipeline().hostVolume()), -1);
}

// Teddy with frames 20-22 blank (a covered lens): they are lost in the first pass, and their
// reports stay while the second pass counts its frames again from 0.
class TeddyWithBlankFrames : public FrameSource {
 public:
  explicit TeddyWithBlankFrames(const FrameSource& data) : data_(data) {}
  int size() const override { return data_.size(); }
  RgbdFrame load(int index) const override {
    RgbdFrame frame = data_.load(index);
    if (index >= 20 && index <= 22) frame.depth = DepthImage(frame.depth.width(), frame.depth.height(), 0.f);
    return frame;
  }
  Intrinsics depthIntrinsics() const override { return data_.depthIntrinsics(); }
  std::string description() const override { return "teddy, frames 20-22 blank"; }

 private:
  const FrameSource& data_;
};

TEST_F(ResumeTest, ASecondPassCheckpointKeepsTheFirstPassLostFrames) {
  const TeddyWithBlankFrames data(*data_);
  const ReconstructionOptions options = secondPassOptions("teddy-blank");
  Reconstruction through(data, options);
  ASSERT_EQ(through.run({}), Reconstruction::Outcome::Finished);
  ASSERT_EQ(through.pass(), 2) << "no loop moved the poses: the second pass was not reached";
  ASSERT_EQ(through.lostFrames().size(), 3u);
  const std::string path = dir_ + "/second_pass_lost.checkpoint";
  {
    Reconstruction stopped(data, options);
    Reconstruction::Callbacks callbacks;
    callbacks.should_stop = [&] { return stopped.pass() == 2 && stopped.framesDone() == 2; };
    ASSERT_EQ(stopped.run(callbacks), Reconstruction::Outcome::Stopped);
    stopped.saveCheckpoint(path);
  }
  Reconstruction resumed(data, options);
  resumed.resume(path);  // 3 lost-frame reports against 2 frames done: not a damaged file
  EXPECT_EQ(resumed.pass(), 2);
  ASSERT_EQ(resumed.run({}), Reconstruction::Outcome::Finished);
  EXPECT_EQ(resumed.lostFrames().size(), 3u);
  ASSERT_EQ(resumed.trajectory().size(), through.trajectory().size());
  EXPECT_EQ(test::firstDifferentBrick(resumed.pipeline().hostVolume(), through.pipeline().hostVolume()), -1);
}

// A first pass that restarted bricks where the camera came back to them (IcpParams::
// restart_stale_bricks; here a tracking window of 8 frames over teddy's first 40) holds only their
// later observations, so every frame is fused again: the scene is every frame fused at the final
// poses, checked against a pipeline given them. A run stopped in its first pass after restarts
// resumes to the same poses and scene, and counts the same restarts (the checkpoint keeps them).
TEST_F(ResumeTest, AFirstPassThatRestartedBricksFusesEveryFrameAgain) {
  ReconstructionOptions options;
  options.params = test::teddyParams();
  options.params.icp.model_window_frames = 8;
  options.device = Device::Cpu;
  options.max_frames = 40;
  options.settings = {{"dataset", "teddy"}};
  Reconstruction through(*data_, options);
  ASSERT_EQ(through.run({}), Reconstruction::Outcome::Finished);
  ASSERT_GT(through.globalReport().bricks_restarted, 0) << "the camera came back to no brick: the test proves nothing";
  EXPECT_EQ(through.pass(), 2);
  ASSERT_EQ(through.trajectory().size(), 40u);
  Pipeline replay(test::teddyParams(), data_->depthIntrinsics(), Device::Cpu);
  for (int i = 0; i < 40; ++i) {
    RgbdFrame frame = data_->load(i);
    frame.T_world_cam_given = through.trajectory()[size_t(i)].T_world_cam;
    replay.processFrame(frame, PoseSource::Given);
  }
  EXPECT_EQ(test::firstDifferentBrick(through.pipeline().hostVolume(), replay.hostVolume()), -1);

  const std::string path = dir_ + "/restarted.checkpoint";
  int64_t restarted_before_stop = 0;
  {
    Reconstruction stopped(*data_, options);
    Reconstruction::Callbacks callbacks;
    callbacks.should_stop = [&] { return stopped.pass() == 1 && stopped.framesDone() == 30; };
    ASSERT_EQ(stopped.run(callbacks), Reconstruction::Outcome::Stopped);
    restarted_before_stop = stopped.pipeline().state().bricks_restarted;
    stopped.saveCheckpoint(path);
  }
  EXPECT_GT(restarted_before_stop, 0);
  Reconstruction resumed(*data_, options);
  resumed.resume(path);
  EXPECT_EQ(resumed.pipeline().state().bricks_restarted, restarted_before_stop);
  ASSERT_EQ(resumed.run({}), Reconstruction::Outcome::Finished);
  EXPECT_EQ(resumed.pass(), 2);
  EXPECT_EQ(resumed.globalReport().bricks_restarted, through.globalReport().bricks_restarted);
  ASSERT_EQ(resumed.trajectory().size(), through.trajectory().size());
  for (size_t i = 0; i < through.trajectory().size(); ++i)
    EXPECT_TRUE(test::sameBits(resumed.trajectory()[i].T_world_cam, through.trajectory()[i].T_world_cam)) << i;
  EXPECT_EQ(test::firstDifferentBrick(resumed.pipeline().hostVolume(), through.pipeline().hostVolume()), -1);
}

// Issue 36: where the loops found agree with the tracked poses (fr1/xyz's first 100 frames: the
// camera comes back over the desk) the loop closure changes nothing: the same poses, bit for
// bit, and the same scene, voxel for voxel, as a run with it off.
TEST(LoopClosureOff, LoopsThatAgreeLeaveTheSceneVoxelForVoxelAsWithoutThem) {
  VF_REQUIRE_DATA(folder, "tum_fr1_xyz_head100");
  const TumDataset data(folder);
  ReconstructionOptions options;
  options.device = Device::Cpu;
  options.settings = {{"dataset", "fr1_xyz_head100"}};
  options.global.loop_closure = false;
  Reconstruction off(data, options);
  ASSERT_EQ(off.run({}), Reconstruction::Outcome::Finished);
  options.global.loop_closure = true;
  Reconstruction on(data, options);
  ASSERT_EQ(on.run({}), Reconstruction::Outcome::Finished);
  ASSERT_GT(on.globalReport().loops_found, 0) << "no loop was found: the test would prove nothing";
  EXPECT_FALSE(on.globalReport().moved());
  EXPECT_EQ(on.pass(), 1);
  ASSERT_EQ(on.trajectory().size(), off.trajectory().size());
  for (size_t i = 0; i < on.trajectory().size(); ++i)
    EXPECT_TRUE(test::sameBits(on.trajectory()[i].T_world_cam, off.trajectory()[i].T_world_cam)) << i;
  EXPECT_EQ(test::firstDifferentBrick(on.pipeline().hostVolume(), off.pipeline().hostVolume()), -1);
}

TEST_F(ResumeTest, MismatchingOrDamagedCheckpointIsRefusedWithAReason) {
  const std::string path = dir_ + "/run.checkpoint";
  {
    Pipeline p(test::teddyParams(), data_->depthIntrinsics(), Device::Cpu);
    fuse(p, *data_, 0, 3);
    RunProgress progress;
    progress.frames_done = 3;
    progress.trajectory.resize(3);
    writeCheckpoint(path, p, progress);
  }
  auto message = [](const std::function<void()>& f) {
    try {
      f();
    } catch (const Error& e) {
      return std::string(e.what());
    }
    return std::string("no error");
  };
  auto restore = [](Pipeline& p, const std::string& file) { readCheckpoint(file, p, {}); };
  // Another voxel size.
  Pipeline other(test::teddyParams(0.01f), data_->depthIntrinsics(), Device::Cpu);
  EXPECT_NE(message([&] { restore(other, path); }).find("holds voxels of 0.005859 m"), std::string::npos);
  // Another camera.
  Intrinsics k = data_->depthIntrinsics();
  k.fx += 1.f;
  Pipeline camera(test::teddyParams(), k, Device::Cpu);
  EXPECT_NE(message([&] { restore(camera, path); }).find("another camera"), std::string::npos);
  // A pipeline that already fused a frame.
  Pipeline busy(test::teddyParams(), data_->depthIntrinsics(), Device::Cpu);
  fuse(busy, *data_, 0, 1);
  EXPECT_NE(message([&] { restore(busy, path); }).find("before its first frame"), std::string::npos);
  // One flipped byte, and a truncated copy.
  std::ifstream in(path, std::ios::binary);
  std::vector<char> bytes{std::istreambuf_iterator<char>(in), std::istreambuf_iterator<char>()};
  ASSERT_GT(bytes.size(), 1000u);
  bytes[bytes.size() / 2] ^= 0x10;
  std::ofstream(dir_ + "/flipped.checkpoint", std::ios::binary).write(bytes.data(), std::streamsize(bytes.size()));
  std::ofstream(dir_ + "/short.checkpoint", std::ios::binary).write(bytes.data(), std::streamsize(bytes.size() / 3));
  Pipeline fresh(test::teddyParams(), data_->depthIntrinsics(), Device::Cpu);
  EXPECT_NE(message([&] { restore(fresh, dir_ + "/flipped.checkpoint"); }).find("checksum"),
            std::string::npos);
  EXPECT_NE(message([&] { restore(fresh, dir_ + "/short.checkpoint"); }).find("short.checkpoint"),
            std::string::npos);
  EXPECT_NE(message([&] { restore(fresh, dir_ + "/missing.checkpoint"); }).find("does not exist"),
            std::string::npos);
  EXPECT_EQ(fresh.framesProcessed(), 0);
}

// The fuzz target's seeds (tests/fuzz/corpus/checkpoint, written by tests/fuzz/make_seeds.py) are
// checkpoints of the format this build reads: a seed of an older format is refused at its version
// field, and fuzzing it mutates nothing behind that check. Each seed is the file without its
// closing FNV-1a checksum (the fuzz target appends it); the pipeline is the target's.
TEST(FuzzSeeds, TheCheckpointSeedsAreReadWhole) {
  const std::filesystem::path corpus = std::filesystem::path(VDBFUSE_SOURCE_DIR) / "tests/fuzz/corpus/checkpoint";
  const std::string dir = test::tempDir("fuzz_seeds");
  int seeds = 0;
  for (const auto& entry : std::filesystem::directory_iterator(corpus)) {
    SCOPED_TRACE(entry.path().string());
    std::ifstream in(entry.path(), std::ios::binary);
    std::vector<char> bytes{std::istreambuf_iterator<char>(in), std::istreambuf_iterator<char>()};
    uint64_t sum = 1469598103934665603ull;
    for (const char c : bytes) sum = (sum ^ uint8_t(c)) * 1099511628211ull;
    bytes.insert(bytes.end(), reinterpret_cast<const char*>(&sum), reinterpret_cast<const char*>(&sum) + sizeof sum);
    const std::string path = dir + "/seed.checkpoint";
    std::ofstream(path, std::ios::binary).write(bytes.data(), std::streamsize(bytes.size()));
    PipelineParams params;
    params.volume.voxel_size_m = 0.02f;
    params.volume.truncation_m = 0.1f;
    const Intrinsics camera{60.f, 60.f, 32.f, 24.f, 64, 48};
    RunSettings settings;
    ASSERT_EQ(test::errorOf([&] { settings = readCheckpointSettings(path); }), "(no error)");
    // The class flag follows the magic (16 bytes), the version (4), the settings and two floats.
    size_t flag_at = 16 + 4 + 4 + 8;
    for (const auto& [key, value] : settings) flag_at += 4 + key.size() + 4 + value.size();
    ASSERT_LT(flag_at, bytes.size());
    Pipeline pipeline(params, camera, Device::Cpu, bytes[flag_at] != 0);
    EXPECT_EQ(test::errorOf([&] { readCheckpoint(path, pipeline, settings); }), "(no error)");
    ++seeds;
  }
  EXPECT_GE(seeds, 3);
}

}  // namespace
}  // namespace vf
