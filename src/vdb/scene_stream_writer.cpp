// writeSceneFromBricks: the scene file written straight from the bricks, one grid after another,
// without the grids in memory.
//
// libopenvdb writes a grid as its descriptor, metadata, transform, topology (root and internal
// nodes, each leaf's value mask) and then every leaf's values in tree order. The topology is
// built here with leaves that own no value buffer (OpenVDB's "partial create"), and libopenvdb
// serialises it as usual; the leaves' values are then filled from the bricks and compressed by
// libopenvdb's own leaf encoding, in parallel into memory, a batch at a time, and appended in
// tree order. The Archive subclass reaches the (protected) header and compression helpers, so
// every byte but the leaf values comes from libopenvdb itself.
#include <openvdb/io/Archive.h>
#include <openvdb/io/Compression.h>
#include <openvdb/io/GridDescriptor.h>
#include <tbb/parallel_for.h>

#include <filesystem>
#include <fstream>
#include <new>
#include <sstream>
#include <unordered_map>

#include "core/atomic_output.h"
#include "core/error.h"
#include "vdb/brick_leaves.h"
#include "vdb/scene_grids.h"

namespace vf {
namespace {

// The bricks that become leaves, their masks, and the order in which libopenvdb visits them.
struct BrickTopology {
  std::vector<size_t> bricks;    // index into the brick volume, in tree (leaf iterator) order
  std::vector<LeafMask> masks;   // active voxels, same order
};

// Leaves per parallel batch: enough work for every core, little memory (compressed values only).
constexpr size_t kLeavesPerBatch = 8192;
constexpr size_t kLeavesPerTask = 256;

class StreamingSceneWriter : public openvdb::io::Archive {
 public:
  explicit StreamingSceneWriter(const BrickVolumeView& v) : v_(v), source_(v), xform_(sceneTransform(v.voxel_size_m)) {
    topology_ = sortedTopology();
  }

  size_t activeVoxelCount() const {
    size_t n = 0;
    for (const LeafMask& m : topology_.masks) n += m.countOn();
    return n;
  }

  void writeTo(std::ostream& os, const openvdb::MetaMap& file_meta) const {
    // As Archive::write: stream state first, then header, file metadata and the grid count.
    // The stream keeps a pointer to this shared pointer (transfer = false), not a copy: it must
    // outlive every use, and each grid's own metadata points back to it when done.
    openvdb::io::StreamMetadata::Ptr stream_meta = std::make_shared<openvdb::io::StreamMetadata>();
    openvdb::io::setStreamMetadataPtr(os, stream_meta, /*transfer=*/false);
    openvdb::io::setDataCompression(os, compression());
    openvdb::io::setWriteGridStatsMetadata(os, isGridStatsMetadataEnabled());
    writeHeader(os, /*seekable=*/true);
    file_meta.writeMeta(os);
    const bool classes = v_.hasClasses();
    const int32_t grid_count = classes ? 5 : 3;
    os.write(reinterpret_cast<const char*>(&grid_count), sizeof grid_count);

    const float trunc = v_.truncation_m;
    auto tsdf = topologyGrid<openvdb::FloatGrid>(trunc, kTsdfGridName);
    tsdf->setGridClass(openvdb::GRID_LEVEL_SET);
    writeGrid(os, stream_meta, *tsdf, [&](size_t n, float* out) { source_.tsdf(n, trunc, out); });
    writeGrid(os, stream_meta, *topologyGrid<openvdb::FloatGrid>(0.f, kWeightGridName),
              [&](size_t n, float* out) { source_.weight(n, out); });
    auto color = topologyGrid<openvdb::Vec3SGrid>(openvdb::Vec3s(0.f), kColorGridName);
    color->setVectorType(openvdb::VEC_INVARIANT);
    writeGrid(os, stream_meta, *color, [&](size_t n, openvdb::Vec3s* out) { source_.color(n, out); });
    if (classes) {
      writeGrid(os, stream_meta, *topologyGrid<openvdb::Int32Grid>(kSceneUnknownClass, kClassGridName),
                [&](size_t n, int32_t* out) { source_.classId(n, out); });
      writeGrid(os, stream_meta, *topologyGrid<openvdb::FloatGrid>(0.f, kClassConfidenceGridName),
                [&](size_t n, float* out) { source_.classConfidence(n, out); });
    }
    os.flush();
  }

 private:
  // The bricks with an observation, ordered as the tree's leaf iterator visits their leaves.
  // The masks (a pass over every voxel) are taken in parallel, once per brick.
  BrickTopology sortedTopology() const {
    std::vector<LeafMask> masks(v_.brick_count);
    std::vector<uint8_t> active(v_.brick_count);
    tbb::parallel_for(size_t(0), v_.brick_count, [&](size_t n) { active[n] = source_.activeMask(n, masks[n]); });
    openvdb::MaskTree order_tree;
    std::unordered_map<openvdb::Coord, size_t, CoordHash> brick_at;
    for (size_t n = 0; n < v_.brick_count; ++n)
      if (active[n]) {
        brick_at.emplace(source_.origin(n), n);
        order_tree.touchLeaf(source_.origin(n));
      }
    BrickTopology t;
    t.bricks.reserve(brick_at.size());
    t.masks.reserve(brick_at.size());
    for (auto leaf = order_tree.cbeginLeaf(); leaf; ++leaf) {
      const size_t n = brick_at.at(leaf->origin());
      t.bricks.push_back(n);
      t.masks.push_back(masks[n]);
    }
    return t;
  }

  struct CoordHash {
    size_t operator()(const openvdb::Coord& c) const {
      return std::hash<int64_t>()((int64_t(c.x()) * 73856093) ^ (int64_t(c.y()) * 19349663) ^ (int64_t(c.z()) * 83492791));
    }
  };

  // A grid with the scene's topology whose leaves hold masks but no values.
  template <class GridT>
  typename GridT::Ptr topologyGrid(typename GridT::ValueType background, const char* name) const {
    using LeafT = typename GridT::TreeType::LeafNodeType;
    auto grid = GridT::create(background);
    grid->setName(name);
    grid->setTransform(xform_);
    setSceneGridStorage(*grid);
    for (size_t i = 0; i < topology_.bricks.size(); ++i) {
      auto* leaf = new LeafT(openvdb::PartialCreate(), source_.origin(topology_.bricks[i]), background, false);
      leaf->setValueMask(topology_.masks[i]);
      grid->tree().addLeaf(leaf);
    }
    return grid;
  }

  // As Archive::writeGrid, with the leaf values from `fill(brick, values)` instead of the tree.
  template <class GridT, class Fill>
  void writeGrid(std::ostream& os, openvdb::io::StreamMetadata::Ptr& file_stream_meta, const GridT& grid,
                 const Fill& fill) const {
    using ValueT = typename GridT::ValueType;
    namespace io = openvdb::io;
    auto stream_meta = std::make_shared<io::StreamMetadata>(*file_stream_meta);
    stream_meta->setHalfFloat(grid.saveFloatAsHalf());
    stream_meta->gridMetadata() = static_cast<const openvdb::MetaMap&>(grid);
    io::setStreamMetadataPtr(os, stream_meta, /*transfer=*/false);

    io::GridDescriptor gd(grid.getName(), grid.type(), grid.saveFloatAsHalf());
    gd.writeHeader(os);
    const int64_t offset_pos = int64_t(os.tellp());
    gd.writeStreamPos(os);  // placeholder, rewritten once the positions are known
    gd.setGridPos(os.tellp());
    setGridCompression(os, grid);
    if (io::getWriteGridStatsMetadata(os)) {
      const auto copy = openvdb::ConstPtrCast<openvdb::GridBase>(grid.copyGrid());
      copy->addStatsMetadata();
      // The leaves here own no values; the grid in memory would have, and reports them.
      const int64_t value_bytes = int64_t(topology_.bricks.size()) * kLeafVoxels * int64_t(sizeof(ValueT));
      copy->insertMeta(openvdb::GridBase::META_FILE_MEM_BYTES, openvdb::Int64Metadata(int64_t(grid.memUsage()) + value_bytes));
      copy->insertMeta(openvdb::GridBase::META_FILE_COMPRESSION,
                       openvdb::StringMetadata(io::compressionToString(io::getDataCompression(os))));
      copy->writeMeta(os);
    } else {
      grid.writeMeta(os);
    }
    grid.writeTransform(os);
    grid.writeTopology(os);  // also points the stream at the background for the leaf encoding
    gd.setBlockPos(os.tellp());
    writeLeafValues<ValueT>(os, fill, grid.saveFloatAsHalf());
    gd.setEndPos(os.tellp());
    os.seekp(offset_pos, std::ios_base::beg);
    gd.writeStreamPos(os);
    gd.seekToEnd(os);
    io::setStreamMetadataPtr(os, file_stream_meta, /*transfer=*/false);
    io::setDataCompression(os, compression());  // per-grid options back to the file's
  }

  template <class ValueT, class Fill>
  void writeLeafValues(std::ostream& os, const Fill& fill, bool to_half) const {
    namespace io = openvdb::io;
    const size_t leaves = topology_.bricks.size();
    std::vector<std::string> chunks((kLeavesPerBatch + kLeavesPerTask - 1) / kLeavesPerTask);
    for (size_t batch = 0; batch < leaves; batch += kLeavesPerBatch) {
      const size_t batch_end = std::min(leaves, batch + kLeavesPerBatch);
      const size_t tasks = (batch_end - batch + kLeavesPerTask - 1) / kLeavesPerTask;
      tbb::parallel_for(size_t(0), tasks, [&](size_t t) {
        std::ostringstream out;
        // The encoding reads the compression flags and the background from the stream.
        io::setDataCompression(out, io::getDataCompression(os));
        io::setGridBackgroundValuePtr(out, io::getGridBackgroundValuePtr(os));
        io::StreamMetadata::Ptr grid_stream_meta = io::getStreamMetadataPtr(os);
        io::setStreamMetadataPtr(out, grid_stream_meta, /*transfer=*/false);
        std::vector<ValueT> values(kLeafVoxels);
        const size_t begin = batch + t * kLeavesPerTask, end = std::min(batch_end, begin + kLeavesPerTask);
        for (size_t i = begin; i < end; ++i) {
          fill(topology_.bricks[i], values.data());
          topology_.masks[i].save(out);  // as LeafNode::writeBuffers: mask, then the values
          io::writeCompressedValues(out, values.data(), openvdb::Index(kLeafVoxels), topology_.masks[i], LeafMask(),
                                    to_half);
        }
        chunks[t] = out.str();
      });
      for (size_t t = 0; t < tasks; ++t) os.write(chunks[t].data(), std::streamsize(chunks[t].size()));
    }
  }

  const BrickVolumeView& v_;
  BrickLeaves source_;
  openvdb::math::Transform::Ptr xform_;
  BrickTopology topology_;
};

}  // namespace

size_t writeSceneFromBricks(const BrickVolumeView& v, const SceneMetadata& meta, const std::string& path) {
  ensureOpenVdbInitialized();
  if (!(v.voxel_size_m > 0)) throw Error(path + ": the brick volume has no voxel size");
  SceneMetadata m = meta;
  m.voxel_size_m = v.voxel_size_m;
  m.truncation_m = v.truncation_m;
  // Written through our own stream, whose state and size are checked (libopenvdb's File hides
  // its stream, which is why writeScene walks the written file; that walk would map the whole
  // file, as large as the bricks, into memory again).
  AtomicFile output(path);
  size_t active_voxels = 0;
  try {
    const StreamingSceneWriter writer(v);
    active_voxels = writer.activeVoxelCount();
    std::ofstream file(output.tempPath(), std::ios_base::out | std::ios_base::binary | std::ios_base::trunc);
    if (!file) throw Error("cannot create " + output.tempPath());
    writer.writeTo(file, sceneFileMetadata(m));
    const std::streamoff written = file.tellp();
    file.close();
    if (!file || written < 0 || std::filesystem::file_size(output.tempPath()) != uintmax_t(written))
      throw Error("the data did not reach the disk whole");
  } catch (const std::bad_alloc&) {
    throw;  // out of memory, not of disk: the command says what lowers the need
  } catch (const std::exception& e) {
    throw Error(path + ": cannot write scene (disk full?): " + e.what());
  }
  output.commit();
  return active_voxels;
}

}  // namespace vf
