#include "fusion/pipeline_state.h"

#include <unistd.h>

#include <cstdio>
#include <cstring>
#include <filesystem>
#include <fstream>
#include <iterator>
#include <optional>
#include <type_traits>
#include <vector>

#include "core/error.h"
#include "fusion/cuda_api.h"
#include "fusion/pipeline.h"

namespace vf {
namespace {

namespace fs = std::filesystem;

constexpr char kMagic[16] = {'V', 'D', 'B', 'F', 'U', 'S', 'E', '-', 'C', 'K', 'P', 'T', '\n', 0, 0, 0};
constexpr uint32_t kVersion = 1;

uint64_t fnv1a(const uint8_t* p, size_t n, uint64_t h = 1469598103934665603ull) {
  for (size_t i = 0; i < n; ++i) h = (h ^ p[i]) * 1099511628211ull;
  return h;
}

// Streams to a temp file beside the target, hashing what it writes; commit() appends the hash,
// syncs and renames. Destroyed without commit(), it removes the temp file.
class AtomicWriter {
 public:
  explicit AtomicWriter(const std::string& path) : path_(path) {
    const fs::path target(path);
    const fs::path dir = target.has_parent_path() ? target.parent_path() : fs::path(".");
    if (!fs::is_directory(dir))
      throw Error("cannot write checkpoint " + path + ": folder " + dir.string() + " does not exist");
    temp_ = (dir / ("." + target.filename().string() + ".tmp" + std::to_string(::getpid()))).string();
    file_ = std::fopen(temp_.c_str(), "wb");
    if (!file_) throw Error("cannot write checkpoint " + path + ": cannot create " + temp_);
  }
  ~AtomicWriter() {
    if (file_) std::fclose(file_);
    if (!committed_) std::remove(temp_.c_str());
  }
  void bytes(const void* p, size_t n) {
    hash_ = fnv1a(static_cast<const uint8_t*>(p), n, hash_);
    ok_ = ok_ && std::fwrite(p, 1, n, file_) == n;
  }
  template <class T>
  void pod(const T& v) {
    static_assert(std::is_trivially_copyable_v<T>);
    bytes(&v, sizeof v);
  }
  void commit() {
    const uint64_t h = hash_;
    ok_ = ok_ && std::fwrite(&h, 1, sizeof h, file_) == sizeof h && std::fflush(file_) == 0 &&
          ::fsync(::fileno(file_)) == 0;
    ok_ = std::fclose(file_) == 0 && ok_;
    file_ = nullptr;
    if (!ok_) throw Error("cannot write checkpoint " + path_ + " (disk full or not writable?)");
    std::error_code ec;
    fs::rename(temp_, path_, ec);
    if (ec) throw Error("cannot write checkpoint " + path_ + ": rename from " + temp_ + " failed: " + ec.message());
    committed_ = true;
  }

 private:
  std::string path_, temp_;
  std::FILE* file_ = nullptr;
  uint64_t hash_ = 1469598103934665603ull;
  bool ok_ = true;
  bool committed_ = false;
};

// Bounds-checked reads from the loaded file; running out of bytes is a truncated checkpoint.
class Reader {
 public:
  Reader(const std::vector<uint8_t>& data, const std::string& path) : data_(data), path_(path) {}
  const uint8_t* bytes(size_t n) {
    if (n > data_.size() - pos_) throw Error("checkpoint " + path_ + " is truncated");
    const uint8_t* p = data_.data() + pos_;
    pos_ += n;
    return p;
  }
  template <class T>
  T pod() {
    T v;
    std::memcpy(&v, bytes(sizeof v), sizeof v);
    return v;
  }
  bool atEnd() const { return pos_ == data_.size(); }

 private:
  const std::vector<uint8_t>& data_;
  const std::string& path_;
  size_t pos_ = 0;
};

// The file with its checksum verified, checksum removed.
std::vector<uint8_t> loadVerified(const std::string& path) {
  std::ifstream in(path, std::ios::binary);
  if (!in) throw Error("checkpoint " + path + " does not exist or cannot be read");
  std::vector<uint8_t> data{std::istreambuf_iterator<char>(in), std::istreambuf_iterator<char>()};
  if (data.size() < sizeof kMagic + sizeof(uint64_t) || std::memcmp(data.data(), kMagic, sizeof kMagic) != 0)
    throw Error(path + " is not a vdbfuse checkpoint");
  uint64_t stored = 0;
  std::memcpy(&stored, data.data() + data.size() - sizeof stored, sizeof stored);
  data.resize(data.size() - sizeof stored);
  if (fnv1a(data.data(), data.size()) != stored)
    throw Error("checkpoint " + path + " is corrupted or truncated (checksum mismatch); start the run again "
                "without --resume");
  return data;
}

struct Header {
  VolumeSpec spec;
  bool with_classes = false;
  Intrinsics intrinsics;
};

void writePose(AtomicWriter& w, const Pose& p) {
  for (int i = 0; i < 16; ++i) w.pod(p.matrix().data()[i]);
}
Pose readPose(Reader& r) {
  Pose p = Pose::Identity();
  for (int i = 0; i < 16; ++i) p.matrix().data()[i] = r.pod<double>();
  return p;
}
void writeOptionalPose(AtomicWriter& w, const std::optional<Pose>& p) {
  w.pod<uint8_t>(p ? 1 : 0);
  writePose(w, p ? *p : Pose::Identity());
}
std::optional<Pose> readOptionalPose(Reader& r) {
  const bool has = r.pod<uint8_t>() != 0;
  const Pose p = readPose(r);
  return has ? std::optional<Pose>(p) : std::nullopt;
}

bool sameBits(float a, float b) { return std::memcmp(&a, &b, sizeof a) == 0; }

std::string describe(const VolumeSpec& s) {
  char text[160];
  std::snprintf(text, sizeof text, "%dx%dx%d voxels of %.3f mm, truncation %.3f mm", s.dims.x, s.dims.y, s.dims.z,
                s.voxel_size_m * 1e3, s.truncation_m * 1e3);
  return text;
}

// Header fields first, annotations next: readPipelineStateAnnotations stops there.
Header readHeader(Reader& r, const std::string& path, std::string& annotations) {
  r.bytes(sizeof kMagic);
  const uint32_t version = r.pod<uint32_t>();
  if (version != kVersion)
    throw Error("checkpoint " + path + " has format version " + std::to_string(version) + ", this vdbfuse reads " +
                std::to_string(kVersion));
  Header h;
  h.spec.dims = r.pod<Vec3i>();
  h.spec.voxel_size_m = r.pod<float>();
  h.spec.truncation_m = r.pod<float>();
  h.spec.origin_m = r.pod<Vec3f>();
  h.with_classes = r.pod<uint8_t>() != 0;
  h.intrinsics.width = r.pod<int32_t>();
  h.intrinsics.height = r.pod<int32_t>();
  h.intrinsics.fx = r.pod<float>();
  h.intrinsics.fy = r.pod<float>();
  h.intrinsics.cx = r.pod<float>();
  h.intrinsics.cy = r.pod<float>();
  const uint64_t n = r.pod<uint64_t>();
  const uint8_t* text = r.bytes(size_t(n));
  annotations.assign(reinterpret_cast<const char*>(text), size_t(n));
  return h;
}

}  // namespace

// Friend of Pipeline (see pipeline.h): the only code outside pipeline.cpp that sees its state.
struct PipelineStateAccess {
  static void save(const Pipeline& const_pipeline, const std::string& path, const std::string& annotations) {
    // hostVolume() only refreshes the host copy of a CUDA volume; the pipeline's state is unchanged.
    Pipeline& p = const_cast<Pipeline&>(const_pipeline);
    const DenseVolume& volume = p.hostVolume();
    const VolumeSpec& spec = volume.spec();
    const VolumeView& v = volume.view();
    AtomicWriter w(path);
    w.bytes(kMagic, sizeof kMagic);
    w.pod(kVersion);
    w.pod(spec.dims);
    w.pod(spec.voxel_size_m);
    w.pod(spec.truncation_m);
    w.pod(spec.origin_m);
    w.pod<uint8_t>(volume.hasClasses() ? 1 : 0);
    w.pod<int32_t>(p.intrinsics_.width);
    w.pod<int32_t>(p.intrinsics_.height);
    w.pod(p.intrinsics_.fx);
    w.pod(p.intrinsics_.fy);
    w.pod(p.intrinsics_.cx);
    w.pod(p.intrinsics_.cy);
    w.pod<uint64_t>(annotations.size());
    w.bytes(annotations.data(), annotations.size());

    w.pod<int32_t>(p.frames_processed_);
    w.pod<int32_t>(p.frames_lost_);
    writePose(w, p.T_world_cam_);
    writePose(w, p.T_world_model_);
    w.pod<uint8_t>(p.has_prediction_ ? 1 : 0);
    writeOptionalPose(w, p.first_given_pose_);
    writeOptionalPose(w, p.last_given_pose_);

    const std::vector<int> allocated = p.allocatedBrickList();
    w.pod<int32_t>(int32_t(allocated.size()));
    w.bytes(allocated.data(), allocated.size() * sizeof(int));
    const std::vector<int> observed = volume.observedBricks();
    w.pod<int32_t>(int32_t(observed.size()));
    for (int brick : observed) {
      const size_t first = size_t(brick) * kBrickVoxels;
      w.pod<int32_t>(brick);
      w.pod<uint32_t>(v.brick_stamp[brick]);
      w.bytes(v.tsdf + first, kBrickVoxels * sizeof(TsdfVoxel));
      w.bytes(v.color + first, kBrickVoxels * sizeof(Rgb8));
      if (v.class_vote) w.bytes(v.class_vote + first, kBrickVoxels * sizeof(uint32_t));
    }
    w.commit();
  }

  static void restore(Pipeline& p, const std::string& path, std::string* annotations) {
    if (p.frames_processed_ != 0)
      throw Error("checkpoint " + path + ": a pipeline can only resume before its first frame");
    const std::vector<uint8_t> data = loadVerified(path);
    Reader r(data, path);
    std::string text;
    const Header h = readHeader(r, path, text);
    const VolumeSpec& spec = p.host_volume_.spec();
    const bool same_volume = h.spec.dims.x == spec.dims.x && h.spec.dims.y == spec.dims.y &&
                             h.spec.dims.z == spec.dims.z && sameBits(h.spec.voxel_size_m, spec.voxel_size_m) &&
                             sameBits(h.spec.truncation_m, spec.truncation_m) &&
                             sameBits(h.spec.origin_m.x, spec.origin_m.x) &&
                             sameBits(h.spec.origin_m.y, spec.origin_m.y) &&
                             sameBits(h.spec.origin_m.z, spec.origin_m.z);
    if (!same_volume)
      throw Error("checkpoint " + path + " holds a volume of " + describe(h.spec) + ", this run asks for " +
                  describe(spec) + "; resume with the same --volume-size, --voxel-size-m and --truncation-m");
    if (h.with_classes != p.host_volume_.hasClasses())
      throw Error("checkpoint " + path + (h.with_classes ? " was fused with --labels; resume with the same --labels"
                                                         : " was fused without --labels; resume without them"));
    const Intrinsics& k = p.intrinsics_;
    if (h.intrinsics.width != k.width || h.intrinsics.height != k.height || !sameBits(h.intrinsics.fx, k.fx) ||
        !sameBits(h.intrinsics.fy, k.fy) || !sameBits(h.intrinsics.cx, k.cx) || !sameBits(h.intrinsics.cy, k.cy))
      throw Error("checkpoint " + path + " was fused with another camera (" + std::to_string(h.intrinsics.width) +
                  "x" + std::to_string(h.intrinsics.height) + ", fx " + std::to_string(h.intrinsics.fx) +
                  "); resume with the same dataset and --intrinsics");

    const int frames_processed = r.pod<int32_t>();
    const int frames_lost = r.pod<int32_t>();
    const Pose T_world_cam = readPose(r);
    const Pose T_world_model = readPose(r);
    const bool has_prediction = r.pod<uint8_t>() != 0;
    const std::optional<Pose> first_given = readOptionalPose(r);
    const std::optional<Pose> last_given = readOptionalPose(r);
    const int brick_count = p.volume_.brickCount();
    auto checkBrick = [&](int brick) {
      if (brick < 0 || brick >= brick_count)
        throw Error("checkpoint " + path + " names brick " + std::to_string(brick) + " outside the volume");
    };
    const int allocated_count = r.pod<int32_t>();
    if (allocated_count < 0 || allocated_count > brick_count || frames_processed < 0 || frames_lost < 0 ||
        frames_lost > frames_processed)
      throw Error("checkpoint " + path + " has inconsistent counters");
    std::vector<int> allocated(static_cast<size_t>(allocated_count));
    std::memcpy(allocated.data(), r.bytes(allocated.size() * sizeof(int)), allocated.size() * sizeof(int));
    for (int b : allocated) checkBrick(b);

    // Voxels go into the host volume; a CUDA pipeline gets them uploaded brick by brick.
    DenseVolume& volume = p.host_volume_;
    volume.clear();
    const VolumeView& host = volume.view();
    const bool cuda = p.device_ == Device::Cuda;
    const int observed = r.pod<int32_t>();
    if (observed < 0 || observed > brick_count) throw Error("checkpoint " + path + " has inconsistent counters");
    for (int i = 0; i < observed; ++i) {
      const int brick = r.pod<int32_t>();
      checkBrick(brick);
      host.brick_stamp[brick] = r.pod<uint32_t>();
      const size_t first = size_t(brick) * kBrickVoxels;
      std::memcpy(host.tsdf + first, r.bytes(kBrickVoxels * sizeof(TsdfVoxel)), kBrickVoxels * sizeof(TsdfVoxel));
      std::memcpy(host.color + first, r.bytes(kBrickVoxels * sizeof(Rgb8)), kBrickVoxels * sizeof(Rgb8));
      if (host.class_vote)
        std::memcpy(host.class_vote + first, r.bytes(kBrickVoxels * sizeof(uint32_t)),
                    kBrickVoxels * sizeof(uint32_t));
      if (cuda) {
        cuda::copyToDevice(p.volume_.tsdf + first, host.tsdf + first, kBrickVoxels * sizeof(TsdfVoxel));
        cuda::copyToDevice(p.volume_.color + first, host.color + first, kBrickVoxels * sizeof(Rgb8));
        if (host.class_vote)
          cuda::copyToDevice(p.volume_.class_vote + first, host.class_vote + first, kBrickVoxels * sizeof(uint32_t));
      }
    }
    if (!r.atEnd()) throw Error("checkpoint " + path + " has trailing bytes (written by another version?)");
    if (cuda)
      cuda::copyToDevice(p.volume_.brick_stamp, host.brick_stamp, size_t(brick_count) * sizeof(uint32_t));
    else
      p.volume_ = host;  // clear() re-mapped the host arrays

    p.setAllocatedBrickList(allocated);
    p.frames_processed_ = frames_processed;
    p.frames_lost_ = frames_lost;
    p.first_given_pose_ = first_given;
    p.last_given_pose_ = last_given;
    // The prediction the next frame tracks against, as the last processFrame() left it.
    p.T_world_cam_ = T_world_model;
    if (has_prediction) p.raycastForTracking();
    p.T_world_cam_ = T_world_cam;
    if (annotations) *annotations = std::move(text);
  }
};

void savePipelineState(const Pipeline& pipeline, const std::string& path, const std::string& annotations) {
  PipelineStateAccess::save(pipeline, path, annotations);
}

void restorePipelineState(Pipeline& pipeline, const std::string& path, std::string* annotations) {
  PipelineStateAccess::restore(pipeline, path, annotations);
}

std::string readPipelineStateAnnotations(const std::string& path) {
  const std::vector<uint8_t> data = loadVerified(path);
  Reader r(data, path);
  std::string text;
  readHeader(r, path, text);
  return text;
}

}  // namespace vf
