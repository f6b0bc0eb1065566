// Structural check of a .vdb file before libopenvdb reads it (see vdb_file_check.h).
//
// The walk mirrors libopenvdb 10's readers (io::Archive::readHeader, io::File::open,
// GridDescriptor::read, MetaMap::readMeta, Transform::read, RootNode/InternalNode/LeafNode
// readTopology and readBuffers, io::readCompressedValues), field for field: where it disagrees
// with them it would reject good files, so tests/vdb/vdb_file_check_test walks files written with
// every compression setting and half floats and requires each grid to end exactly where its
// descriptor says.
#include "vdb/vdb_file_check.h"

#include <array>
#include <cctype>
#include <cstdint>
#include <cstring>
#include <istream>
#include <map>
#include <openvdb/Metadata.h>
#include <openvdb/io/Compression.h>
#include <vector>

#include "core/byte_reader.h"
#include "core/error.h"
#include "core/mapped_file.h"
#include "vdb/openvdb_init.h"

namespace vf {
namespace {

constexpr int64_t kVdbMagic = 0x56444220;
constexpr uint32_t kFirstFormat = 222;  // OPENVDB_FILE_VERSION_NODE_MASK_COMPRESSION
constexpr uint32_t kLastFormat = 224;   // OPENVDB_FILE_VERSION_MULTIPASS_IO, what OpenVDB 10 writes
constexpr uint32_t kCompressZip = 0x1, kCompressActiveMask = 0x2, kCompressBlosc = 0x4;
constexpr char kUniqueNameSeparator = '\x1e';      // GridDescriptor's "name[N]" suffix
constexpr const char* kHalfFloatSuffix = "_HalfFloat";
constexpr size_t kLeafMaskBytes = 64;              // 8^3 bits
constexpr uint64_t kLeafValues = 512;

// io::readCompressedValues' per-node flag (io/Compression.h).
enum NodeValueFlags : int8_t {
  kNoMaskOrInactiveVals = 0,
  kNoMaskAndMinusBg = 1,
  kNoMaskAndOneInactiveVal = 2,
  kMaskAndNoInactiveVals = 3,
  kMaskAndOneInactiveVal = 4,
  kMaskAndTwoInactiveVals = 5,
  kNoMaskAndAllVals = 6,
};



uint32_t loadU32(const uint8_t* p) {
  uint32_t v;
  std::memcpy(&v, p, 4);
  return v;
}

uint64_t countOnBits(const uint8_t* mask, size_t bytes) {
  uint64_t on = 0;
  for (size_t i = 0; i < bytes; i += 8) {
    uint64_t word;
    std::memcpy(&word, mask + i, 8);
    on += uint64_t(__builtin_popcountll(word));
  }
  return on;
}

// A blosc chunk's 16-byte header says how many bytes it decompresses to (bytes 4-7) and how many
// compressed bytes it spans (bytes 12-15); blosc trusts both when it decompresses.
// `padded_to` > 0: arrays shorter than that were zero-padded up to it before compression
// (points::bloscCompress, which DelayedLoadMetadata uses, pads to BLOSC_PAD_BYTES = 128).
void checkBloscHeader(ByteReader& c, const uint8_t* chunk, uint64_t chunk_bytes, uint64_t expected_bytes,
                      const std::string& what, uint64_t padded_to = 0) {
  if (chunk_bytes < 16) c.fail(what + ": blosc chunk of " + std::to_string(chunk_bytes) + " bytes has no header");
  const uint64_t decompressed = loadU32(chunk + 4);
  const bool padded = expected_bytes < padded_to && decompressed == padded_to;
  if (decompressed != expected_bytes && !padded)
    c.fail(what + ": blosc chunk decompresses to " + std::to_string(loadU32(chunk + 4)) + " bytes, expected " +
           std::to_string(expected_bytes));
  if (loadU32(chunk + 12) > chunk_bytes)
    c.fail(what + ": blosc chunk claims " + std::to_string(loadU32(chunk + 12)) + " compressed bytes but holds " +
           std::to_string(chunk_bytes));
}

// An istream over bytes already in memory, for libopenvdb's chunk decoders.
class MemoryStreamBuf : public std::streambuf {
 public:
  MemoryStreamBuf(const uint8_t* data, size_t size) {
    char* begin = const_cast<char*>(reinterpret_cast<const char*>(data));
    setg(begin, begin, begin + size);
  }
};

// Decodes one compressed chunk (its int64 size prefix included) with libopenvdb's own decoder.
void decodeChunk(ByteReader& c, const uint8_t* chunk, size_t chunk_bytes, uint64_t bytes, uint32_t compression) {
  MemoryStreamBuf buffer(chunk, chunk_bytes);
  std::istream in(&buffer);
  std::vector<char> values(bytes);
  try {
    if (compression & kCompressBlosc)
      openvdb::io::bloscFromStream(in, values.data(), bytes);
    else
      openvdb::io::unzipFromStream(in, values.data(), bytes);
  } catch (const std::exception& e) {
    c.fail(std::string("node values do not decompress: ") + e.what());
  }
}

// io::readData: `bytes` bytes of values, raw or as one zip/blosc chunk whose int64 size prefix is
// negative for data stored uncompressed. With `decode`, a compressed chunk is also decompressed.
void checkValueData(ByteReader& c, uint64_t bytes, uint32_t compression, bool decode) {
  if (!(compression & (kCompressBlosc | kCompressZip))) {
    c.take(bytes, "node values");
    return;
  }
  const uint8_t* start = c.take(8, "compressed chunk size");
  int64_t stated;
  std::memcpy(&stated, start, 8);
  if (stated <= 0) {
    if (stated != -int64_t(bytes))
      c.fail("uncompressed chunk of " + std::to_string(stated) + " (negated) bytes where " + std::to_string(bytes) +
             " are expected");
    c.take(bytes, "uncompressed node values");
    return;
  }
  const uint8_t* chunk = c.take(uint64_t(stated), "compressed node values");
  if (compression & kCompressBlosc) checkBloscHeader(c, chunk, uint64_t(stated), bytes, "node values");
  if (decode) decodeChunk(c, start, 8 + size_t(stated), bytes, compression);
}

// What a grid's values look like in the file.
struct GridLayout {
  size_t value_bytes = 0;  // sizeof(ValueType): background, tiles, inactive values
  size_t half_bytes = 0;   // a value saved as half float; 0 for integer grids
  uint32_t compression = 0;
  bool from_half = false;
  uint64_t storedValueBytes() const { return from_half && half_bytes ? half_bytes : value_bytes; }
};

// The grid type names of FloatGrid, Vec3SGrid and Int32Grid (Grid::gridType()).
GridLayout layoutOfGridType(ByteReader& c, const std::string& grid_name, const std::string& type) {
  GridLayout g;
  if (type == "Tree_float_5_4_3") {
    g.value_bytes = 4;
    g.half_bytes = 2;
  } else if (type == "Tree_vec3s_5_4_3") {
    g.value_bytes = 12;
    g.half_bytes = 6;
  } else if (type == "Tree_int32_5_4_3") {
    g.value_bytes = 4;
  } else {
    c.fail("grid '" + grid_name + "' has type " + type + "; vdbfuse reads float, vec3s and int32 grids");
  }
  return g;
}

// io::readCompressedValues for a node of `node_values` values with value mask `value_mask`.
// Internal nodes are allocated before their values are decoded and libopenvdb leaks the node when
// decoding throws, so their chunks are decoded here (`decode`); leaves belong to the tree by then.
void checkCompressedValues(ByteReader& c, uint64_t node_values, const uint8_t* value_mask, const GridLayout& g,
                           bool decode) {
  const int8_t flags = c.read<int8_t>("node value flags");
  if (flags == kNoMaskAndOneInactiveVal || flags == kMaskAndOneInactiveVal || flags == kMaskAndTwoInactiveVals) {
    c.take(g.value_bytes, "inactive value");
    if (flags == kMaskAndTwoInactiveVals) c.take(g.value_bytes, "second inactive value");
  }
  if (flags == kMaskAndNoInactiveVals || flags == kMaskAndOneInactiveVal || flags == kMaskAndTwoInactiveVals)
    c.take(node_values / 8, "selection mask");
  uint64_t count = node_values;
  if ((g.compression & kCompressActiveMask) && flags != kNoMaskAndAllVals)
    count = countOnBits(value_mask, node_values / 8);
  // HalfReader reads nothing at all for zero values; readData still reads a chunk size.
  if (g.from_half && g.half_bytes && count == 0) return;
  checkValueData(c, count * g.storedValueBytes(), g.compression, decode);
}

using LeafMasks = std::vector<const uint8_t*>;

// InternalNode::readTopology (log2dim 5: upper nodes, 4: lower nodes) and its children's; collects
// the value mask of every leaf in the order readBuffers visits them.
void checkInternalTopology(ByteReader& c, int log2dim, const GridLayout& g, LeafMasks& leaves) {
  const uint64_t values = uint64_t(1) << (3 * log2dim);
  const uint8_t* child_mask = c.take(values / 8, "child mask");
  const uint8_t* value_mask = c.take(values / 8, "value mask");
  checkCompressedValues(c, values, value_mask, g, /*decode=*/true);
  for (uint64_t byte = 0; byte < values / 8; ++byte) {
    for (int bit = 0; bit < 8; ++bit) {
      if (!(child_mask[byte] >> bit & 1)) continue;
      if (log2dim == 5)
        checkInternalTopology(c, 4, g, leaves);
      else
        leaves.push_back(c.take(kLeafMaskBytes, "leaf value mask"));
    }
  }
}

// Tree::readTopology then Tree::readBuffers.
void checkTree(ByteReader& c, const GridLayout& g) {
  c.read<int32_t>("buffer count");
  c.take(g.value_bytes, "background value");
  const uint32_t tiles = c.read<uint32_t>("root tile count");
  const uint32_t children = c.read<uint32_t>("root child count");
  const uint64_t tile_bytes = 12 + g.value_bytes + 1;
  if (tiles > c.remaining() / tile_bytes) c.fail(std::to_string(tiles) + " root tiles do not fit in the file");
  for (uint32_t n = 0; n < tiles; ++n) {
    c.take(12 + g.value_bytes, "root tile");
    // RootNode reads the flag straight into a bool: any byte but 0 or 1 is undefined behaviour.
    if (c.read<uint8_t>("root tile active flag") > 1) c.fail("a root tile's active flag is neither 0 nor 1");
  }
  const uint64_t min_child_bytes = 12 + 2 * 4096 + 1;
  if (children > c.remaining() / min_child_bytes)
    c.fail(std::to_string(children) + " root children do not fit in the file");

  // RootNode keeps its children in a std::map by origin and readBuffers visits them in the map's
  // (x, y, z) order, not the file's. A repeated origin would replace (and leak) the earlier child.
  std::map<std::array<int32_t, 3>, LeafMasks> root_children;
  for (uint32_t n = 0; n < children; ++n) {
    std::array<int32_t, 3> origin;
    std::memcpy(origin.data(), c.take(12, "root child origin"), 12);
    const auto inserted = root_children.try_emplace(origin);
    if (!inserted.second) c.fail("two root children at the same origin");
    checkInternalTopology(c, 5, g, inserted.first->second);
  }

  for (const auto& child : root_children) {
    for (const uint8_t* topology_mask : child.second) {
      // File::open streams are seekable: LeafNode::readBuffers skips this copy of the mask and
      // decodes with the topology's, so both must agree for the value count to be what we check.
      const uint8_t* mask = c.take(kLeafMaskBytes, "leaf value mask");
      if (std::memcmp(mask, topology_mask, kLeafMaskBytes) != 0)
        c.fail("a leaf's value mask differs between the tree topology and the leaf buffers");
      checkCompressedValues(c, kLeafValues, mask, g, /*decode=*/false);
    }
  }
}

// DelayedLoadMetadata::readValue: a count, then one mask byte and one uint64 per leaf, each array
// raw or blosc-compressed. libopenvdb sizes its arrays by the count before it reads them.
void checkDelayedLoadMetadata(ByteReader& c, uint32_t value_bytes) {
  if (value_bytes == 0) return;
  const size_t start = c.offset();
  const uint32_t count = c.read<uint32_t>("delayed-load count");
  // One entry per leaf, and every leaf takes at least its 64-byte mask in the file.
  if (count > c.size() / kLeafMaskBytes)
    c.fail("delayed-load metadata lists " + std::to_string(count) + " leaves, more than the file can hold");
  const uint32_t mask_bytes = c.read<uint32_t>("delayed-load mask size");
  constexpr uint64_t kBloscPadBytes = 128;
  if (mask_bytes > 0)
    checkBloscHeader(c, c.take(mask_bytes, "delayed-load masks"), mask_bytes, count, "delayed-load masks",
                     kBloscPadBytes);
  else
    c.take(count, "delayed-load masks");
  const uint32_t sizes_bytes = c.read<uint32_t>("delayed-load sizes size");
  if (sizes_bytes == UINT32_MAX) {
    // no compressed sizes stored
  } else if (sizes_bytes > 0) {
    checkBloscHeader(c, c.take(sizes_bytes, "delayed-load sizes"), sizes_bytes, uint64_t(count) * 8,
                     "delayed-load sizes", kBloscPadBytes);
  } else {
    c.take(uint64_t(count) * 8, "delayed-load sizes");
  }
  if (c.offset() - start > value_bytes) c.fail("delayed-load metadata is longer than its stated size");
  c.seek(int64_t(start + value_bytes), "delayed-load metadata end");
}

struct MetaMapFacts {
  bool saved_as_half = false;  // GridBase::saveFloatAsHalf(): "is_saved_as_half_float", else false
};

// MetaMap::readMeta. A registered fixed-size type is read with its own size whatever the file
// states, so a different stated size would shift every later read.
MetaMapFacts checkMetaMap(ByteReader& c, const std::string& owner) {
  MetaMapFacts facts;
  const uint32_t count = c.read<uint32_t>(owner + " metadata count");
  if (count > c.remaining() / 12)
    c.fail(owner + " metadata count " + std::to_string(count) + " exceeds what the file holds");
  for (uint32_t i = 0; i < count; ++i) {
    const std::string name = c.readString(owner + " metadata name");
    const std::string type = c.readString(owner + " metadata type");
    const uint32_t value_bytes = c.read<uint32_t>(owner + " metadata size");
    const std::string what = owner + " metadata '" + name + "' (" + type + ")";
    if (type == "__delayedload" && openvdb::Metadata::isRegisteredType(type)) {
      checkDelayedLoadMetadata(c, value_bytes);
      continue;
    }
    const uint8_t* value = c.take(value_bytes, what);
    if (type != openvdb::StringMetadata::staticTypeName() && openvdb::Metadata::isRegisteredType(type)) {
      const uint32_t expected = openvdb::Metadata::createMetadata(type)->size();
      if (value_bytes != expected)
        c.fail(what + " states " + std::to_string(value_bytes) + " bytes, its type has " + std::to_string(expected));
    }
    // BoolMetadata reads its byte straight into a bool, like the root tiles.
    if (type == openvdb::BoolMetadata::staticTypeName() && value_bytes == 1 && value[0] > 1)
      c.fail(what + " is neither 0 nor 1");
    if (name == "is_saved_as_half_float") {  // GridBase::META_SAVE_HALF_FLOAT
      if (type != openvdb::BoolMetadata::staticTypeName()) c.fail(what + " is not a bool");
      facts.saved_as_half = value[0] != 0;
    }
  }
  return facts;
}

// Transform::read: the map's registered name, then its fields (math/Maps.h read()).
void checkTransform(ByteReader& c, const std::string& grid_name) {
  static const std::map<std::string, uint64_t> kMapBytes = {
      {"AffineMap", 128},         {"UnitaryMap", 128},        {"ScaleMap", 120},
      {"UniformScaleMap", 120},   {"TranslationMap", 24},     {"ScaleTranslateMap", 144},
      {"UniformScaleTranslateMap", 144},
  };
  const std::string type = c.readString("transform type");
  const auto it = kMapBytes.find(type);
  if (it == kMapBytes.end())
    c.fail("grid '" + grid_name + "' has a " + type + " transform; vdbfuse reads linear transforms only");
  c.take(it->second, type);
}

struct Descriptor {
  std::string unique_name, grid_name, type, instance_parent;
  bool half_suffix = false;
  int64_t grid_pos = 0, end_pos = 0;
};

// io::Archive::readGrid from the descriptor's grid position. True if it ended at the stated end.
// Without `with_tree`, only what File::readGridMetadata reads: the grid's metadata and transform.
bool checkGrid(ByteReader& c, const Descriptor& d, bool with_tree) {
  c.seek(d.grid_pos, "grid '" + d.grid_name + "' position");
  GridLayout g = layoutOfGridType(c, d.grid_name, d.type);
  g.compression = c.read<uint32_t>("grid compression flags");
  g.from_half = checkMetaMap(c, "grid '" + d.grid_name + "'").saved_as_half;
  if (g.from_half != d.half_suffix)
    c.fail("grid '" + d.grid_name + "': its descriptor and its metadata disagree on half-float storage");
  checkTransform(c, d.grid_name);
  if (!with_tree) return false;
  if (d.instance_parent.empty()) checkTree(c, g);
  if (int64_t(c.offset()) > d.end_pos) c.fail("grid '" + d.grid_name + "' runs past its stated end");
  return int64_t(c.offset()) == d.end_pos;
}

std::vector<Descriptor> checkHeaderAndDescriptors(ByteReader& c) {
  if (c.read<int64_t>("magic number") != kVdbMagic) c.fail("not an OpenVDB file (wrong magic number)");
  const uint32_t format = c.read<uint32_t>("file format version");
  if (format < kFirstFormat || format > kLastFormat)
    c.fail("file format " + std::to_string(format) + "; vdbfuse reads formats " + std::to_string(kFirstFormat) +
           " to " + std::to_string(kLastFormat));
  c.take(8, "library version");
  if (c.read<uint8_t>("grid offsets flag") == 0)
    c.fail("written as a stream without grid offsets; save it with openvdb::io::File");
  // The uuid is ASCII, 8-4-4-4-12 hex digits; libopenvdb reads it with operator>>, which skips
  // leading white space and would leave the stream failed on anything else.
  const uint8_t* uuid = c.take(36, "uuid");
  for (int i = 0; i < 36; ++i) {
    const bool dash_position = i == 8 || i == 13 || i == 18 || i == 23;
    if (dash_position ? uuid[i] != '-' : !std::isxdigit(uuid[i])) c.fail("malformed uuid");
  }
  checkMetaMap(c, "file");

  const int32_t grid_count = c.read<int32_t>("grid count");
  if (grid_count > 0 && uint64_t(grid_count) > c.remaining() / 36)
    c.fail("grid count " + std::to_string(grid_count) + " exceeds what the file holds");
  std::vector<Descriptor> descriptors;
  for (int32_t i = 0; i < grid_count; ++i) {
    Descriptor d;
    d.unique_name = c.readString("grid name");
    d.grid_name = d.unique_name.substr(0, d.unique_name.find(kUniqueNameSeparator));
    d.type = c.readString("grid type");
    const size_t suffix = std::strlen(kHalfFloatSuffix);
    if (d.type.size() >= suffix && d.type.compare(d.type.size() - suffix, suffix, kHalfFloatSuffix) == 0) {
      d.half_suffix = true;
      d.type.resize(d.type.size() - suffix);
    }
    d.instance_parent = c.readString("instance parent name");
    d.grid_pos = c.read<int64_t>("grid position");
    c.read<int64_t>("block position");
    d.end_pos = c.read<int64_t>("grid end position");
    if (d.grid_pos < int64_t(c.offset()) || d.end_pos < d.grid_pos || uint64_t(d.end_pos) > c.size())
      c.fail("grid '" + d.grid_name + "' has positions " + std::to_string(d.grid_pos) + ".." +
             std::to_string(d.end_pos) + " outside the file");
    c.seek(d.end_pos, "grid '" + d.grid_name + "' end");  // the next descriptor follows the grid
    descriptors.push_back(std::move(d));
  }
  return descriptors;
}

}  // namespace

namespace {

VdbFileWalk checkVdbFile(const std::string& path, const std::vector<std::string>& grids_to_read, bool with_trees) {
  ensureOpenVdbInitialized();  // the metadata type registry
  const MappedFile file(path, "scene file");
  ByteReader c(file.data(), file.size(), path + ": damaged or unsupported .vdb file");
  const std::vector<Descriptor> descriptors = checkHeaderAndDescriptors(c);
  VdbFileWalk walk;
  const auto check = [&](const Descriptor& d) {
    ++walk.grids_checked;
    if (checkGrid(c, d, with_trees)) ++walk.grids_ending_at_stated_end;
  };

  // libopenvdb picks the first descriptor of a name; check every one of that name.
  for (const std::string& name : grids_to_read) {
    for (const Descriptor& d : descriptors) {
      if (d.grid_name != name) continue;
      check(d);
      if (d.instance_parent.empty()) continue;
      // An instance shares its parent's tree: check that grid too, whichever of the name it is.
      const std::string parent = d.instance_parent.substr(0, d.instance_parent.find(kUniqueNameSeparator));
      bool found = false;
      for (const Descriptor& p : descriptors) {
        if (p.grid_name != parent) continue;
        if (!p.instance_parent.empty()) c.fail("grid '" + name + "' is an instance of an instance");
        if (p.type != d.type) c.fail("grid '" + name + "' is an instance of a grid of another type");
        check(p);
        found = true;
      }
      if (!found) c.fail("grid '" + name + "' is an instance of a missing grid '" + parent + "'");
    }
  }
  return walk;
}

}  // namespace

VdbFileWalk checkVdbFileStructure(const std::string& path, const std::vector<std::string>& grids_to_read) {
  return checkVdbFile(path, grids_to_read, /*with_trees=*/true);
}

VdbFileWalk checkVdbFileHeaders(const std::string& path, const std::vector<std::string>& grids_to_read) {
  return checkVdbFile(path, grids_to_read, /*with_trees=*/false);
}

}  // namespace vf
