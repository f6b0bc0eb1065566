#include "fusion/checkpoint.h"

#include <algorithm>
#include <cmath>
#include <cstring>
#include <map>
#include <optional>
#include <set>
#include <sstream>
#include <tuple>
#include <type_traits>

#include "core/atomic_output.h"
#include "core/byte_reader.h"
#include "core/error.h"
#include "core/mapped_file.h"
#include "fusion/pipeline.h"

namespace vf {
namespace {

constexpr char kMagic[16] = {'V', 'D', 'B', 'F', 'U', 'S', 'E', '-', 'C', 'K', 'P', 'T', '\n', 0, 0, 0};
// 1: dense volume with a text annotation block; 2: sparse bricks; 3: the prediction window;
// 4: poses only for the frames that have one, lost frames with their reason, the driver's state;
// 5: each brick's last marking stamp (tracking's window of recent bricks).
// 6: the tracker's stretches of frames whose view left directions to the motion prior.
// 7: the tracker's maps (a new one after a loss the old one could not recover), per keyframe.
// 8: the tracker's last second of good poses (slam/recent_motion.h), not only its last step.
// 9: the tracker's last good pose and time no longer stored beside that second (its last sample).
// 10: the count of bricks the first pass restarted (PipelineState::bricks_restarted).
// A new version also needs the fuzz seeds rewritten (tests/fuzz/make_seeds.py; resume_test checks).
constexpr uint32_t kVersion = 10;

uint64_t fnv1a(const uint8_t* p, size_t n, uint64_t h = 1469598103934665603ull) {
  for (size_t i = 0; i < n; ++i) h = (h ^ p[i]) * 1099511628211ull;
  return h;
}

// Streams into an AtomicFile, hashing what it writes; commit() appends the hash.
class HashingWriter {
 public:
  explicit HashingWriter(const std::string& path) : file_(path) {}
  void bytes(const void* p, size_t n) {
    hash_ = fnv1a(static_cast<const uint8_t*>(p), n, hash_);
    file_.write(p, n);
  }
  template <class T>
  void pod(const T& v) {
    static_assert(std::is_trivially_copyable_v<T>);
    bytes(&v, sizeof v);
  }
  void string(const std::string& s) {
    pod<uint32_t>(uint32_t(s.size()));
    bytes(s.data(), s.size());
  }
  void pose(const Pose& p) {
    for (int i = 0; i < 16; ++i) pod(p.matrix().data()[i]);
  }
  void commit() {
    const uint64_t h = hash_;
    file_.write(&h, sizeof h);
    file_.commit();
  }

 private:
  AtomicFile file_;
  uint64_t hash_ = 1469598103934665603ull;
};

Pose readPose(ByteReader& r) {
  Pose p = Pose::Identity();
  for (int i = 0; i < 16; ++i) p.matrix().data()[i] = r.read<double>("pose");
  return p;
}

uint32_t readCount(ByteReader& r, const std::string& what, uint64_t bytes_each) {
  const uint32_t n = r.read<uint32_t>(what + " count");
  if (bytes_each > 0 && n > r.remaining() / bytes_each) r.fail(what + " count " + std::to_string(n) + " exceeds the file");
  return n;
}

bool sameBits(float a, float b) { return std::memcmp(&a, &b, sizeof a) == 0; }

// The checksum only shows that the file is as written, not that what was written makes sense (a
// forged or buggy file with a NaN pose resumed and wrote a trajectory of nan). Every value read
// is checked against what a run can produce, and the file is named when one is not.
bool isRigid(const Pose& p) {
  const Eigen::Matrix4d& m = p.matrix();
  if (!m.allFinite() || m(3, 0) != 0 || m(3, 1) != 0 || m(3, 2) != 0 || m(3, 3) != 1) return false;
  const Eigen::Matrix3d R = m.topLeftCorner<3, 3>();
  // Poses are products of many rotations: rounding leaves them orthonormal to ~1e-12.
  return (R.transpose() * R - Eigen::Matrix3d::Identity()).cwiseAbs().maxCoeff() < 1e-6 && R.determinant() > 0;
}

void requireRigid(const Pose& p, const std::string& what, const std::string& path) {
  if (isRigid(p)) return;
  std::ostringstream rows;
  for (int r = 0; r < 4; ++r)
    for (int c = 0; c < 4; ++c) rows << p.matrix()(r, c) << (c < 3 ? " " : r < 3 ? " / " : "");
  throw Error("checkpoint " + path + ": " + what + " is not a rigid motion with finite numbers (rows " + rows.str() +
              "); start the run again");
}

void requireSaneProgress(const PipelineState& s, const RunProgress& progress, const std::string& path) {
  requireRigid(s.T_world_cam, "the current camera pose", path);
  requireRigid(s.T_world_model, "the pose of the tracking prediction", path);
  if (s.last_given_pose) requireRigid(*s.last_given_pose, "the last recorded pose", path);
  const auto fail = [&path](const std::string& why) {
    throw Error("checkpoint " + path + ": " + why + "; start the run again");
  };
  for (size_t i = 0; i < progress.trajectory.size(); ++i) {
    const StampedPose& p = progress.trajectory[i];
    if (!std::isfinite(p.timestamp)) fail("frame " + std::to_string(i) + " has a timestamp that is not finite");
    requireRigid(p.T_world_cam, "the pose of frame " + std::to_string(i), path);
  }
  if (s.frames_lost < 0 || s.frames_lost > s.frames_processed)
    fail(std::to_string(s.frames_lost) + " frames lost of " + std::to_string(s.frames_processed) + " processed");
  // (The second pass counts its frames again from 0 while the first pass's lost frames stay: the
  // session, which knows the pass and the dataset, checks the reports against them.)
  std::set<int> lost;
  for (const LostFrame& l : progress.lost)
    if (l.index < 0 || !lost.insert(l.index).second)
      fail("lost-frame report for frame " + std::to_string(l.index) + (l.index < 0 ? "" : ", twice"));
}

void requireSaneWindow(const Image<float>& window, const std::string& path) {
  const size_t n = size_t(window.width()) * size_t(window.height());
  for (size_t i = 0; i < n; ++i)
    if (!(std::isfinite(window.data()[i]) && window.data()[i] >= 0.f))
      throw Error("checkpoint " + path + ": the saved prediction window holds a depth of " +
                  std::to_string(window.data()[i]) + " m; start the run again");
}

// Each brick once: a coordinate given twice would take two slots of the hash for one brick.
void requireDistinctBricks(const HostBrickVolume& bricks, const std::string& path) {
  std::vector<Vec3i> coords = bricks.coords;
  const auto less = [](const Vec3i& a, const Vec3i& b) { return std::tie(a.x, a.y, a.z) < std::tie(b.x, b.y, b.z); };
  std::sort(coords.begin(), coords.end(), less);
  for (size_t i = 1; i < coords.size(); ++i)
    if (!less(coords[i - 1], coords[i]))
      throw Error("checkpoint " + path + ": brick (" + std::to_string(coords[i].x) + ", " + std::to_string(coords[i].y) +
                  ", " + std::to_string(coords[i].z) + ") is saved twice; start the run again");
}

struct Header {
  RunSettings settings;
  float voxel_size_m = 0, truncation_m = 0;
  bool with_classes = false;
  Intrinsics camera;
};

void checkHeader(const Header& h, const Pipeline& pipeline, const RunSettings& settings, const std::string& path) {
  std::map<std::string, std::string> saved(h.settings.begin(), h.settings.end());
  for (const auto& [key, value] : settings) {
    const auto it = saved.find(key);
    const std::string before = it == saved.end() ? "(unset)" : it->second;
    if (before != value)
      throw Error("checkpoint " + path + " belongs to a run with " + key + " = " + before + ", this run has " + key +
                  " = " + value + "; resume with the same dataset and options, or start again");
  }
  const VolumeSpec& spec = pipeline.params().volume;
  if (!sameBits(h.voxel_size_m, spec.voxel_size_m) || !sameBits(h.truncation_m, spec.truncation_m))
    throw Error("checkpoint " + path + " holds voxels of " + std::to_string(h.voxel_size_m) + " m (truncation " +
                std::to_string(h.truncation_m) + " m), this run asks for " + std::to_string(spec.voxel_size_m) +
                " m (" + std::to_string(spec.truncation_m) + " m)");
  if (h.with_classes != pipeline.withClasses())
    throw Error("checkpoint " + path + (h.with_classes ? " was fused with class labels; resume with the same labels"
                                                       : " was fused without class labels; resume without them"));
  const Intrinsics& k = pipeline.intrinsics();
  if (h.camera.width != k.width || h.camera.height != k.height || !sameBits(h.camera.fx, k.fx) ||
      !sameBits(h.camera.fy, k.fy) || !sameBits(h.camera.cx, k.cx) || !sameBits(h.camera.cy, k.cy))
    throw Error("checkpoint " + path + " was fused with another camera (" + std::to_string(h.camera.width) + "x" +
                std::to_string(h.camera.height) + ", fx " + std::to_string(h.camera.fx) +
                "); resume with the same dataset and intrinsics");
}

}  // namespace

void writeCheckpoint(const std::string& path, Pipeline& pipeline, const RunProgress& progress) {
  const BrickVolumeView bricks = pipeline.hostVolume();
  const PipelineState& s = pipeline.state();
  const Intrinsics& k = pipeline.intrinsics();
  HashingWriter w(path);
  w.bytes(kMagic, sizeof kMagic);
  w.pod(kVersion);
  w.pod<uint32_t>(uint32_t(progress.settings.size()));
  for (const auto& [key, value] : progress.settings) {
    w.string(key);
    w.string(value);
  }
  w.pod(bricks.voxel_size_m);
  w.pod(bricks.truncation_m);
  w.pod<uint8_t>(bricks.hasClasses() ? 1 : 0);
  w.pod<int32_t>(k.width);
  w.pod<int32_t>(k.height);
  w.pod(k.fx);
  w.pod(k.fy);
  w.pod(k.cx);
  w.pod(k.cy);

  w.pod<int32_t>(s.frames_processed);
  w.pod<int32_t>(s.frames_lost);
  w.pose(s.T_world_cam);
  w.pose(s.T_world_model);
  w.pod<uint8_t>(s.has_prediction ? 1 : 0);
  w.pod<uint8_t>(s.prediction_windowed ? 1 : 0);
  if (s.prediction_windowed) {
    const Image<float> window = pipeline.predictionWindow();
    w.pod<int32_t>(window.width());
    w.pod<int32_t>(window.height());
    w.bytes(window.data(), size_t(window.width()) * window.height() * sizeof(float));
  }
  w.pod<uint8_t>(s.last_given_pose ? 1 : 0);
  w.pose(s.last_given_pose.value_or(Pose::Identity()));

  w.pod<int32_t>(progress.frames_done);
  w.pod<uint32_t>(uint32_t(progress.trajectory.size()));
  for (const StampedPose& p : progress.trajectory) {
    w.pod(p.timestamp);
    w.pose(p.T_world_cam);
  }
  w.pod<uint32_t>(uint32_t(progress.lost.size()));
  for (const LostFrame& l : progress.lost) {
    w.pod<int32_t>(l.index);
    w.pod<uint8_t>(uint8_t(l.reason));
    w.string(l.name);
    w.string(l.why);
  }
  w.pod<uint64_t>(progress.session.size());
  w.bytes(progress.session.data(), progress.session.size());
  w.pod<uint8_t>(s.last_frame_committed ? 1 : 0);
  w.pose(s.last_motion);
  w.pod<int64_t>(s.bricks_restarted);

  const size_t n = bricks.brick_count, voxels = n * kBrickVoxels;
  w.pod<uint32_t>(uint32_t(n));
  w.bytes(bricks.coords, n * sizeof(Vec3i));
  w.bytes(bricks.tsdf, voxels * sizeof(TsdfVoxel));
  w.bytes(bricks.color, voxels * sizeof(Rgb8));
  if (bricks.hasClasses()) w.bytes(bricks.class_vote, voxels * sizeof(uint32_t));
  const std::vector<uint32_t> stamps = pipeline.brickStamps();  // tracking's window of recent bricks
  w.bytes(stamps.data(), stamps.size() * sizeof(uint32_t));
  w.commit();
}

namespace {

// The file with its checksum verified, and a reader positioned after the settings.
struct VerifiedFile {
  explicit VerifiedFile(const std::string& path) : file(path, "checkpoint"), reader(nullptr, 0, "") {
    if (file.size() < sizeof kMagic + sizeof(uint32_t) + sizeof(uint64_t) ||
        std::memcmp(file.data(), kMagic, sizeof kMagic) != 0)
      throw Error(path + " is not a vdbfuse checkpoint");
    const size_t body = file.size() - sizeof(uint64_t);
    uint64_t stored = 0;
    std::memcpy(&stored, file.data() + body, sizeof stored);
    if (fnv1a(file.data(), body) != stored)
      throw Error("checkpoint " + path + " is corrupted or truncated (checksum mismatch); start the run again");
    reader = ByteReader(file.data(), body, "checkpoint " + path + " is damaged");
    reader.take(sizeof kMagic, "magic");
    const uint32_t version = reader.read<uint32_t>("version");
    if (version != kVersion)
      throw Error("checkpoint " + path + " has format version " + std::to_string(version) + ", this vdbfuse reads " +
                  std::to_string(kVersion) + "; start the run again");
    const uint32_t setting_count = readCount(reader, "setting", 8);
    for (uint32_t i = 0; i < setting_count; ++i) {
      std::string key = reader.readString("setting name");
      settings.emplace_back(std::move(key), reader.readString("setting value"));
    }
  }
  MappedFile file;
  ByteReader reader;
  RunSettings settings;
};

}  // namespace

RunSettings readCheckpointSettings(const std::string& path) { return VerifiedFile(path).settings; }

RunProgress readCheckpoint(const std::string& path, Pipeline& pipeline, const RunSettings& settings) {
  VerifiedFile verified(path);
  ByteReader& r = verified.reader;
  Header h;
  h.settings = verified.settings;
  h.voxel_size_m = r.read<float>("voxel size");
  h.truncation_m = r.read<float>("truncation");
  h.with_classes = r.read<uint8_t>("class flag") != 0;
  h.camera.width = r.read<int32_t>("camera width");
  h.camera.height = r.read<int32_t>("camera height");
  h.camera.fx = r.read<float>("fx");
  h.camera.fy = r.read<float>("fy");
  h.camera.cx = r.read<float>("cx");
  h.camera.cy = r.read<float>("cy");
  checkHeader(h, pipeline, settings, path);

  PipelineState s;
  s.frames_processed = r.read<int32_t>("frame count");
  s.frames_lost = r.read<int32_t>("lost frame count");
  s.T_world_cam = readPose(r);
  s.T_world_model = readPose(r);
  s.has_prediction = r.read<uint8_t>("prediction flag") != 0;
  s.prediction_windowed = r.read<uint8_t>("prediction window flag") != 0;
  Image<float> window;
  if (s.prediction_windowed) {
    const int32_t width = r.read<int32_t>("prediction window width");
    const int32_t height = r.read<int32_t>("prediction window height");
    if (width <= 0 || height <= 0 || width > 16384 || height > 16384 ||
        uint64_t(width) * uint64_t(height) * sizeof(float) > r.remaining())
      r.fail("a prediction window of " + std::to_string(width) + "x" + std::to_string(height) + " pixels is impossible");
    window.resize(width, height);
    std::memcpy(window.data(), r.take(size_t(width) * height * sizeof(float), "prediction window"),
                size_t(width) * height * sizeof(float));
  }
  const bool has_given = r.read<uint8_t>("recorded pose flag") != 0;
  const Pose given = readPose(r);
  if (has_given) s.last_given_pose = given;

  RunProgress progress;
  progress.settings = h.settings;
  progress.frames_done = r.read<int32_t>("frames done");
  const uint32_t poses = readCount(r, "trajectory", sizeof(double) * 17);
  progress.trajectory.resize(poses);
  for (StampedPose& p : progress.trajectory) {
    p.timestamp = r.read<double>("timestamp");
    p.T_world_cam = readPose(r);
  }
  const uint32_t lost = readCount(r, "lost frame", 13);
  for (uint32_t i = 0; i < lost; ++i) {
    LostFrame l;
    l.index = r.read<int32_t>("lost frame index");
    const uint8_t reason = r.read<uint8_t>("lost frame reason");
    if (reason > uint8_t(LostReason::Collapse)) r.fail("lost frame reason " + std::to_string(reason) + " is unknown");
    l.reason = LostReason(reason);
    l.name = r.readString("lost frame name");
    l.why = r.readString("lost frame report");
    progress.lost.push_back(std::move(l));
  }
  const uint64_t session_bytes = r.read<uint64_t>("session state size");
  if (session_bytes > r.remaining()) r.fail("session state of " + std::to_string(session_bytes) + " bytes exceeds the file");
  const uint8_t* session = r.take(session_bytes, "session state");
  progress.session.assign(session, session + session_bytes);
  s.last_frame_committed = r.read<uint8_t>("last frame flag") != 0;
  s.last_motion = readPose(r);
  s.bricks_restarted = r.read<int64_t>("restarted brick count");
  if (s.bricks_restarted < 0) r.fail("restarted brick count " + std::to_string(s.bricks_restarted) + " is negative");
  if (progress.frames_done < 0 || progress.frames_done != s.frames_processed)
    throw Error("checkpoint " + path + ": frame counts and trajectory disagree");
  requireSaneProgress(s, progress, path);
  if (s.prediction_windowed) requireSaneWindow(window, path);

  HostBrickVolume bricks;
  bricks.voxel_size_m = h.voxel_size_m;
  bricks.truncation_m = h.truncation_m;
  bricks.with_classes = h.with_classes;
  const uint64_t per_brick = sizeof(Vec3i) + sizeof(uint32_t) +
                             kBrickVoxels * (sizeof(TsdfVoxel) + sizeof(Rgb8) + (h.with_classes ? sizeof(uint32_t) : 0));
  const uint32_t n = readCount(r, "brick", per_brick);
  bricks.resize(n);
  const size_t voxels = size_t(n) * kBrickVoxels;
  // A run that fused nothing saves no brick: the empty arrays have no storage to copy into (a null
  // pointer, which memcpy must not get even for 0 bytes).
  const auto copy = [&r](void* dst, size_t bytes, const char* what) {
    const uint8_t* src = r.take(bytes, what);
    if (bytes > 0) std::memcpy(dst, src, bytes);
  };
  copy(bricks.coords.data(), n * sizeof(Vec3i), "brick coordinates");
  copy(bricks.tsdf.data(), voxels * sizeof(TsdfVoxel), "tsdf");
  copy(bricks.color.data(), voxels * sizeof(Rgb8), "colour");
  if (h.with_classes) copy(bricks.class_vote.data(), voxels * sizeof(uint32_t), "class votes");
  std::vector<uint32_t> stamps(n);
  copy(stamps.data(), size_t(n) * sizeof(uint32_t), "brick stamps");
  for (const uint32_t stamp : stamps)
    if (stamp > uint32_t(s.frames_processed))
      throw Error("checkpoint " + path + " has a brick stamped after its last frame (damaged?)");
  if (!r.atEnd()) throw Error("checkpoint " + path + " has trailing bytes (written by another version?)");
  requireDistinctBricks(bricks, path);
  try {
    pipeline.restore(s, bricks, window, stamps);
  } catch (const Error& e) {
    throw Error("checkpoint " + path + ": " + e.what());
  }
  return progress;
}

}  // namespace vf
