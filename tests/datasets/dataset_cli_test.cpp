// The dataset readers end to end through `vdbfuse reconstruct` and `vdbfuse evaluate`: layouts
// are detected, poses go in and come out equal with --poses given, a wrong depth scale or an
// unknown layout is a clear error, and evaluate --mesh gives the distances it was built with.
#include <gtest/gtest.h>

#include <cctype>
#include <cmath>
#include <cstdlib>
#include <filesystem>

#include "dataset_fixtures.h"
#include "io/mesh_io.h"
#include "io/trajectory_io.h"
#include "test_data.h"

namespace vf {
namespace {

namespace fs = std::filesystem;

const std::string kSmall = " --voxel-size-m 0.02 -q -f";

std::string run(const std::string& args, int& status) {
  return test::runCommand(std::string(VDBFUSE_EXE) + " " + args, status);
}

// The number after `label` in the output (e.g. "rmse" -> 0.000).
double figure(const std::string& log, const std::string& label) {
  for (size_t at = log.find(label); at != std::string::npos; at = log.find(label, at + 1)) {
    const char* text = log.c_str() + at + label.size();
    if (!std::isspace(static_cast<unsigned char>(*text))) continue;
    char* end = nullptr;
    const double value = std::strtod(text, &end);
    if (end != text) return value;
  }
  return NAN;
}

// The trajectory written with --poses given is the input's up to one rigid motion (today the
// first pose is moved to the origin): relative poses must be equal.
void expectSamePosesUpToRigidMotion(const Trajectory& out, const std::vector<Pose>& in) {
  ASSERT_EQ(out.size(), in.size());
  for (size_t i = 0; i < in.size(); ++i) {
    const Pose rel_out = out[0].T_world_cam.inverse() * out[i].T_world_cam;
    const Pose rel_in = in[0].inverse() * in[i];
    EXPECT_LT((rel_out.matrix() - rel_in.matrix()).cwiseAbs().maxCoeff(), 2e-6) << "frame " << i;
    EXPECT_NEAR(out[i].timestamp, double(i) / 30.0, 1e-6);
  }
}

void roundTrip(const std::string& name, const std::string& folder, const std::vector<Pose>& poses,
               const std::string& expect_in_log) {
  const std::string out = test::tempDir(name + "_out") + "/scene.vdb";
  int status = 0;
  std::string log = run("reconstruct " + folder + " --poses given -o " + out + kSmall, status);
  ASSERT_EQ(status, 0) << log;
  const Trajectory trajectory = readTumTrajectory(fs::path(out).replace_extension(".txt").string());
  expectSamePosesUpToRigidMotion(trajectory, poses);
  // evaluate takes the dataset folder as the ground truth.
  log = run("evaluate --trajectory " + fs::path(out).replace_extension(".txt").string() + " --groundtruth " + folder,
            status);
  ASSERT_EQ(status, 0) << log;
  EXPECT_LT(figure(log, "rmse"), 0.001) << log;  // cm
  EXPECT_NE(log.find(std::to_string(poses.size()) + " pairs"), std::string::npos) << log;
  log = run("reconstruct " + folder + " --max-frames 1 -o " + out + " --voxel-size-m 0.02 -f",
            status);
  EXPECT_NE(log.find(expect_in_log), std::string::npos) << log;
}

TEST(DatasetCli, ScanNetPosesRoundTripWithPosesGiven) {
  const std::string dir = test::tempDir("cli_scannet");
  const std::vector<Pose> poses = test::fixturePoses(5);
  test::writeScanNet(dir, poses);
  roundTrip("cli_scannet", dir, poses, "ScanNet");
}

TEST(DatasetCli, RedwoodPosesRoundTripWithPosesGiven) {
  const std::string dir = test::tempDir("cli_redwood");
  const std::vector<Pose> poses = test::fixturePoses(5);
  test::writeRedwood(dir, poses);
  roundTrip("cli_redwood", dir, poses, "Redwood");
}

TEST(DatasetCli, SevenScenesAndReplicaPosesRoundTripWithPosesGiven) {
  const std::vector<Pose> poses = test::fixturePoses(4);
  const std::string seven = test::tempDir("cli_7scenes");
  test::writeSevenScenes(seven, poses);
  roundTrip("cli_7scenes", seven, poses, "7-Scenes/3DMatch");
  const std::string replica = test::writeReplica(test::tempDir("cli_replica"), poses);
  roundTrip("cli_replica", replica, poses, "Replica");
}

TEST(DatasetCli, UnregisteredColourTurnsThePhotometricTermOffUnlessForced) {
  // ScanNet's colour comes from another camera, resized to the depth size.
  const std::string dir = test::tempDir("cli_photometric");
  test::writeScanNet(dir, test::fixturePoses(2));
  const std::string out = dir + "_scene.vdb";
  int status = 0;
  std::string log = run("reconstruct " + dir + " -o " + out + " --voxel-size-m 0.02 -f", status);
  ASSERT_EQ(status, 0) << log;
  EXPECT_NE(log.find("photometric ICP term off"), std::string::npos) << log;
  log = run("reconstruct " + dir + " -o " + out + " --photometric on --voxel-size-m 0.02 -f", status);
  ASSERT_EQ(status, 0) << log;
  EXPECT_EQ(log.find("photometric ICP term off"), std::string::npos) << log;
  log = run("reconstruct " + dir + " -o " + out + " --photometric maybe" + kSmall, status);
  EXPECT_NE(status, 0);
}

TEST(DatasetCli, WrongDepthScaleNamesFolderScaleAndOption) {
  const std::vector<Pose> poses = test::fixturePoses(2);
  const std::string near = test::tempDir("cli_scale_near");
  test::writeSevenScenes(near, poses, 10);  // decimetres read as millimetres: 0.002 m
  const std::string out = test::tempDir("cli_scale_out") + "/s.vdb";
  int status = 0;
  std::string log = run("reconstruct " + near + " -o " + out + kSmall, status);
  EXPECT_NE(status, 0);
  EXPECT_NE(log.find(near), std::string::npos) << log;
  EXPECT_NE(log.find("scale of 1000 units per metre"), std::string::npos) << log;
  EXPECT_NE(log.find("--depth-scale"), std::string::npos) << log;
  EXPECT_FALSE(fs::exists(out)) << "no output after the error";
  // Telling the scale fixes it, and the poses still round-trip.
  log = run("reconstruct " + near + " --depth-scale 10 --poses given -o " + out + kSmall, status);
  ASSERT_EQ(status, 0) << log;

  const std::string far = test::tempDir("cli_scale_far");
  test::writeSevenScenes(far, poses, 30000);  // reads 57 m
  log = run("reconstruct " + far + " -o " + out + kSmall, status);
  EXPECT_NE(status, 0);
  EXPECT_NE(log.find("outside the plausible 0.2-20 m"), std::string::npos) << log;
  log = run("reconstruct " + far + " -o " + out + " --depth-scale 0" + kSmall, status);
  EXPECT_NE(status, 0);
  EXPECT_NE(log.find("--depth-scale 0"), std::string::npos) << log;
}

TEST(DatasetCli, UnknownLayoutListsTheKnownOnes) {
  const std::string dir = test::tempDir("cli_unknown");
  test::writeText(dir + "/notes.txt", "nothing here");
  int status = 0;
  // Outputs beside the input folder: one inside it is refused (it would change the input).
  const std::string log = run("reconstruct " + dir + " -o " + dir + "_s.vdb" + kSmall, status);
  EXPECT_NE(status, 0);
  EXPECT_NE(log.find(dir + ": not a folder of a known RGB-D layout"), std::string::npos) << log;
  for (const char* layout : {"tum", "r3d", "r3d-export", "7scenes", "replica", "scannet", "redwood"})
    EXPECT_NE(log.find(std::string("  ") + layout + " "), std::string::npos) << layout << "\n" << log;
  // A 7-Scenes/3DMatch scene folder holds its frames in seq-XX folders: say which to give.
  const std::string scene = test::tempDir("cli_scene");
  test::writeSevenScenes(scene + "/seq-02", test::fixturePoses(2));
  test::writeSevenScenes(scene + "/seq-01", test::fixturePoses(2));
  const std::string seq = run("reconstruct " + scene + " -o " + dir + "/s.vdb" + kSmall, status);
  EXPECT_NE(status, 0);
  EXPECT_NE(seq.find(scene + ": not a sequence itself, but it holds 2 (seq-01 (7scenes), seq-02 (7scenes)); name the "
                     "folder of the one to read, e.g. " + scene + "/seq-01"), std::string::npos) << seq;
  // A forced format that does not fit says what it expected.
  const std::string seven = test::tempDir("cli_forced");
  test::writeSevenScenes(seven, test::fixturePoses(2));
  const std::string forced = run("reconstruct " + seven + " --format replica -o " + dir + "/s.vdb" + kSmall, status);
  EXPECT_NE(status, 0);
  EXPECT_NE(forced.find("traj.txt"), std::string::npos) << forced;
}

// Issue 37: the shared Replica sample wraps its sequence in office0/ (cam_params.json beside it),
// and a new user names the wrapper.
TEST(DatasetCli, AWrapperFolderNamesTheSequenceInside) {
  VF_REQUIRE_DATA(replica, "replica_office0");
  const std::string dir = test::tempDir("cli_wrapper");
  int status = 0;
  const std::string log = run("reconstruct " + replica + " -o " + dir + "/s.vdb" + kSmall, status);
  EXPECT_NE(status, 0);
  EXPECT_NE(log.find("it holds 1 (office0 (replica)); name the folder of the one to read, e.g. " + replica + "/office0"),
            std::string::npos) << log;
}

TEST(DatasetCli, UnzippedRecord3dFolderIsDetected) {
  VF_REQUIRE_DATA(capture, "record3d_dance_head200.r3d");
  const std::string dir = test::tempDir("cli_r3d_folder");
  fs::create_directories(dir + "/rgbd");
  int status = 0;
  const std::string unzip = test::runCommand("cd " + dir + " && python3 -c \"import zipfile; z = zipfile.ZipFile('" +
                                                 capture +
                                                 "'); [z.extract(n) for n in z.namelist() if n == 'metadata' or "
                                                 "n.split('/')[-1].split('.')[0] in ('0', '1', '2')]\"",
                                             status);
  ASSERT_EQ(status, 0) << unzip;
  const std::string log = run("reconstruct " + dir + " --poses given -o " + dir + "_s.vdb" + kSmall, status);
  ASSERT_EQ(status, 0) << log;
  EXPECT_EQ(readTumTrajectory(dir + "_s.txt").size(), 3u);
  // Issue 37 item 2: evaluate scores against the phone's (ARKit) poses, from the capture itself
  // and from its unzipped folder; the run used those poses, so the error is nil.
  for (const std::string& truth : {capture, dir}) {
    SCOPED_TRACE(truth);
    const std::string eval = run("evaluate -t " + dir + "_s.txt -g " + truth, status);
    ASSERT_EQ(status, 0) << eval;
    EXPECT_LT(figure(eval, "rmse"), 0.001) << eval;  // cm
    EXPECT_NE(eval.find("3 pairs"), std::string::npos) << eval;
    // Three frames give two RPE pairs: the ATE stands, the RPE says why it has no figure.
    EXPECT_NE(eval.find("RPE: none (RPE needs at least 3 frame pairs"), std::string::npos) << eval;
  }
}

TriangleMesh sphere(float r, int rings = 120, int segments = 240) {
  TriangleMesh m;
  for (int i = 0; i <= rings; ++i)
    for (int j = 0; j < segments; ++j) {
      const double th = M_PI * i / rings, ph = 2 * M_PI * j / segments;
      m.positions.push_back({float(r * std::sin(th) * std::cos(ph)), float(r * std::sin(th) * std::sin(ph)),
                             float(r * std::cos(th))});
    }
  for (int i = 0; i < rings; ++i)
    for (int j = 0; j < segments; ++j) {
      const int a = i * segments + j, b = i * segments + (j + 1) % segments;
      m.triangles.push_back({a, a + segments, b});
      m.triangles.push_back({b, a + segments, b + segments});
    }
  return m;
}

TEST(EvaluateMesh, SphereAgainstOneTwoCentimetresLargerGivesTwoCentimetres) {
  const std::string dir = test::tempDir("eval_sphere");
  writePly(sphere(1.0f), dir + "/ref.ply", false);
  writePly(sphere(1.02f), dir + "/rec.ply", false);
  int status = 0;
  std::string log = run("evaluate --mesh " + dir + "/rec.ply --reference " + dir + "/ref.ply --samples 200000", status);
  ASSERT_EQ(status, 0) << log;
  EXPECT_NEAR(figure(log, "accuracy"), 2.0, 0.01) << log;  // cm, median
  EXPECT_NEAR(figure(log, "completion"), 100.0, 1e-9) << log;
  EXPECT_NEAR(figure(log, "F-score@5cm"), 1.0, 1e-9) << log;
  log = run("evaluate --mesh " + dir + "/rec.ply --reference " + dir + "/ref.ply --samples 200000 --max-distance 0.01",
            status);
  ASSERT_EQ(status, 0) << log;
  EXPECT_NEAR(figure(log, "completion"), 0.0, 1e-9) << log;
  EXPECT_NEAR(figure(log, "F-score@1cm"), 0.0, 1e-9) << log;
  log = run("evaluate --mesh " + dir + "/rec.ply", status);
  EXPECT_NE(status, 0);
  EXPECT_NE(log.find("--reference"), std::string::npos) << log;
}

// A wall 2 m ahead, fused from the fixture's 4 frames with their poses, against a 20 x 20 m
// reference wall: the trajectory saw only a small part, and only that part counts.
TEST(EvaluateMesh, TrajectoryAlignsTheMeshAndLimitsCompletionToWhatWasSeen) {
  const std::vector<Pose> poses = test::fixturePoses(4);
  const std::string dir = test::tempDir("eval_wall");
  const std::string replica = test::writeReplica(dir, poses);
  TriangleMesh wall;
  wall.positions = {{-10, -10, 2}, {10, -10, 2}, {10, 10, 2}, {-10, 10, 2}};
  wall.triangles = {{0, 1, 2}, {0, 2, 3}};
  writePly(wall, dir + "/wall.ply", false);
  int status = 0;
  std::string log = run("reconstruct " + replica + " --poses given -o " + dir + "/s.vdb" + kSmall, status);
  ASSERT_EQ(status, 0) << log;
  log = run("mesh " + dir + "/s.vdb --axes camera -o " + dir + "/s.ply", status);  // the scene's own frame
  ASSERT_EQ(status, 0) << log;
  const std::string eval = "evaluate --mesh " + dir + "/s.ply --reference " + dir + "/wall.ply --samples 200000";
  log = run(eval + " --trajectory " + dir + "/s.txt --dataset " + replica, status);
  ASSERT_EQ(status, 0) << log;
  EXPECT_NE(log.find("alignment       the first pose's correspondence"), std::string::npos) << log;
  EXPECT_LT(figure(log, "accuracy"), 0.5) << log;  // cm
  EXPECT_GT(figure(log, "completion"), 90.0) << log;
  EXPECT_NE(log.find("seen by 4 frames"), std::string::npos) << log;
  // The default PLY export is z-up; its header records the rotation, which evaluate undoes, so
  // the figures are those of the camera-frame mesh (scored as written, it would miss the wall).
  const std::string camera_log = log;
  ASSERT_EQ((run("mesh " + dir + "/s.vdb -o " + dir + "/s_zup.ply", status), status), 0);
  log = run("evaluate --mesh " + dir + "/s_zup.ply --reference " + dir + "/wall.ply --samples 200000 --trajectory " + dir +
                "/s.txt --dataset " + replica,
            status);
  ASSERT_EQ(status, 0) << log;
  EXPECT_NE(log.find("written --axes z-up, brought back into the scene's frame"), std::string::npos) << log;
  EXPECT_NEAR(figure(log, "accuracy"), figure(camera_log, "accuracy"), 0.01) << log;
  EXPECT_NEAR(figure(log, "completion"), figure(camera_log, "completion"), 0.1) << log;
  // Two exports compare as before: a vdbfuse reference is brought back the same way.
  log = run("evaluate --mesh " + dir + "/s_zup.ply --reference " + dir + "/s.ply --samples 200000", status);
  ASSERT_EQ(status, 0) << log;
  EXPECT_LT(figure(log, "accuracy"), 0.01) << log;  // cm: the same surface
  log = run("evaluate --mesh " + dir + "/s.ply --reference " + dir + "/s_zup.ply --samples 200000", status);
  ASSERT_EQ(status, 0) << log;
  EXPECT_LT(figure(log, "accuracy"), 0.01) << log;
  // Without the dataset nothing is culled, and the wall is mostly not reconstructed. Without
  // the trajectory nothing is aligned: --poses given fused in the recorded world frame, which is
  // the reference's, so the mesh lies on the wall as it is.
  log = run(eval + " --trajectory " + dir + "/s.txt --groundtruth " + replica, status);
  ASSERT_EQ(status, 0) << log;
  EXPECT_LT(figure(log, "completion"), 5.0) << log;
  log = run(eval, status);
  ASSERT_EQ(status, 0) << log;
  EXPECT_NE(log.find("alignment       none"), std::string::npos) << log;
  EXPECT_LT(figure(log, "accuracy"), 0.5) << log;
}

}  // namespace
}  // namespace vf
