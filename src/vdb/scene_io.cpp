// Reading and writing the scene document (.vdb). Metadata keys are prefixed "vdbfuse_" so that
// other tools (Blender, Houdini) show them without clashing with their own.
#include <openvdb/io/File.h>
#include <tbb/parallel_for.h>

#include <cmath>
#include <filesystem>
#include <new>
#include <stdexcept>
#include <nlohmann/json.hpp>

#include "core/atomic_output.h"
#include "core/error.h"
#include "core/similar_names.h"
#include "core/version.h"
#include "vdb/scene.h"
#include "vdb/scene_grids.h"
#include "vdb/vdb_file_check.h"

namespace vf {
namespace {

namespace fs = std::filesystem;

constexpr const char* kMetaVoxelSize = "vdbfuse_voxel_size_m";
constexpr const char* kMetaTruncation = "vdbfuse_truncation_m";
constexpr const char* kMetaClasses = "vdbfuse_classes";
constexpr const char* kMetaSource = "vdbfuse_source";
constexpr const char* kMetaFrameCount = "vdbfuse_frame_count";
constexpr const char* kMetaVersion = "vdbfuse_software_version";
constexpr const char* kMetaUp = "vdbfuse_up";
constexpr const char* kMetaForward = "vdbfuse_forward";
constexpr const char* kMetaUpSource = "vdbfuse_up_source";
constexpr const char* kMetaIntrinsics = "vdbfuse_depth_fx_fy_cx_cy";
constexpr const char* kMetaImageSize = "vdbfuse_depth_width_height";
constexpr const char* kMetaTrajectory = "vdbfuse_trajectory_tum";
constexpr const char* kMetaSourceOptions = "vdbfuse_source_options";

// Up, heading and camera: written only when known, checked when read (a file is outside data).
void writeFrameMeta(const SceneMetadata& m, openvdb::MetaMap& meta) {
  if (norm(m.up_world) > 0) {
    meta.insertMeta(kMetaUp, openvdb::Vec3SMetadata({m.up_world.x, m.up_world.y, m.up_world.z}));
    meta.insertMeta(kMetaForward, openvdb::Vec3SMetadata({m.forward_world.x, m.forward_world.y, m.forward_world.z}));
    meta.insertMeta(kMetaUpSource, openvdb::StringMetadata(m.up_source));
  }
  const Intrinsics& k = m.depth_intrinsics;
  if (k.valid()) {
    meta.insertMeta(kMetaIntrinsics, openvdb::Vec4SMetadata({k.fx, k.fy, k.cx, k.cy}));
    meta.insertMeta(kMetaImageSize, openvdb::Vec2IMetadata({k.width, k.height}));
  }
}

void readFrameMeta(const openvdb::MetaMap& meta, SceneMetadata& m, const std::string& path) {
  auto unitVector = [&](const char* key) {
    const auto v = meta.getMetadata<openvdb::Vec3SMetadata>(key);
    if (!v) throw Error(path + ": metadata '" + kMetaUp + "' without '" + key + "'");
    const Vec3f u{v->value().x(), v->value().y(), v->value().z()};
    if (!isFinite(u) || std::fabs(norm(u) - 1.f) > 1e-3f)
      throw Error(path + ": metadata '" + key + "' is not a unit vector");
    return u;
  };
  if (meta.getMetadata<openvdb::Vec3SMetadata>(kMetaUp)) {
    m.up_world = unitVector(kMetaUp);
    m.forward_world = unitVector(kMetaForward);
    if (std::fabs(dot(m.up_world, m.forward_world)) > 1e-3f)
      throw Error(path + ": metadata '" + kMetaForward + "' is not perpendicular to '" + kMetaUp + "'");
    if (auto v = meta.getMetadata<openvdb::StringMetadata>(kMetaUpSource)) m.up_source = v->value();
  }
  const auto k = meta.getMetadata<openvdb::Vec4SMetadata>(kMetaIntrinsics);
  const auto size = meta.getMetadata<openvdb::Vec2IMetadata>(kMetaImageSize);
  if (k && size) {
    Intrinsics& in = m.depth_intrinsics;
    in = {k->value()[0], k->value()[1], k->value()[2], k->value()[3], size->value()[0], size->value()[1]};
    if (!std::isfinite(in.cx) || !std::isfinite(in.cy) || !(in.fx > 0 && in.fx < 1e6f) || !(in.fy > 0 && in.fy < 1e6f) ||
        in.width <= 0 || in.height <= 0 || in.width > 100000 || in.height > 100000)
      throw Error(path + ": metadata '" + kMetaIntrinsics + "' / '" + kMetaImageSize + "' is not a camera");
  }
}

std::string classesToJson(const ClassTable& table) {
  nlohmann::json arr = nlohmann::json::array();
  for (const ClassInfo& c : table.classes)
    arr.push_back({{"id", c.id}, {"name", c.name}, {"color", {c.color.r, c.color.g, c.color.b}}});
  return arr.dump();
}

ClassTable classesFromJson(const std::string& text, const std::string& path) {
  ClassTable table;
  try {
    for (const auto& item : nlohmann::json::parse(text)) {
      ClassInfo c;
      c.id = item.at("id").get<int>();
      c.name = item.at("name").get<std::string>();
      const auto& rgb = item.at("color");
      c.color = {rgb.at(0).get<uint8_t>(), rgb.at(1).get<uint8_t>(), rgb.at(2).get<uint8_t>(), 255};
      table.classes.push_back(c);
    }
  } catch (const nlohmann::json::exception& e) {
    throw Error(path + ": metadata '" + kMetaClasses + "' is not a valid class table: " + e.what());
  }
  // Two classes with one id: the faces of one would be written into the other's mesh.
  table.requireUnique(path + ": metadata '" + kMetaClasses + "'");
  return table;
}

template <class GridT>
typename GridT::Ptr findGrid(const openvdb::GridPtrVec& grids, const char* name, const std::string& path,
                             bool required) {
  for (const auto& base : grids) {
    if (!base || base->getName() != name) continue;
    auto grid = openvdb::gridPtrCast<GridT>(base);
    if (!grid)
      throw Error(path + ": grid '" + name + "' has type " + base->valueType() + ", expected " +
                  openvdb::typeNameAsString<typename GridT::ValueType>());
    return grid;
  }
  if (required) throw Error(path + ": not a vdbfuse scene: it has no '" + name + "' grid");
  return nullptr;
}

}  // namespace

openvdb::MetaMap sceneFileMetadata(const SceneMetadata& m) {
  openvdb::MetaMap meta;
  meta.insertMeta(kMetaVoxelSize, openvdb::FloatMetadata(m.voxel_size_m));
  meta.insertMeta(kMetaTruncation, openvdb::FloatMetadata(m.truncation_m));
  meta.insertMeta(kMetaClasses, openvdb::StringMetadata(classesToJson(m.classes)));
  meta.insertMeta(kMetaSource, openvdb::StringMetadata(m.source));
  meta.insertMeta(kMetaFrameCount, openvdb::Int32Metadata(m.frame_count));
  meta.insertMeta(kMetaVersion, openvdb::StringMetadata(m.software_version.empty() ? std::string(VDBFUSE_VERSION_STRING)
                                                                                   : m.software_version));
  writeFrameMeta(m, meta);
  if (!m.trajectory_tum.empty()) meta.insertMeta(kMetaTrajectory, openvdb::StringMetadata(m.trajectory_tum));
  if (!m.source_options_json.empty()) meta.insertMeta(kMetaSourceOptions, openvdb::StringMetadata(m.source_options_json));
  return meta;
}

void writeScene(const Scene& scene, const std::string& path) {
  ensureOpenVdbInitialized();
  const SceneGrids& g = scene.grids();
  if (!g.tsdf) throw Error(path + ": cannot write a scene without a tsdf grid");
  openvdb::GridPtrVec grids;
  for (openvdb::GridBase::Ptr grid :
       {openvdb::GridBase::Ptr(g.tsdf), openvdb::GridBase::Ptr(g.weight), openvdb::GridBase::Ptr(g.color),
        openvdb::GridBase::Ptr(g.class_id), openvdb::GridBase::Ptr(g.class_confidence)})
    if (grid) grids.push_back(grid);
  for (const openvdb::GridBase::Ptr& grid : grids) setSceneGridStorage(*grid);
  writeVdbFileAtomic(path, grids, sceneFileMetadata(scene.meta), "scene");
}

void writeVdbFileAtomic(const std::string& path, const openvdb::GridPtrVec& grids, const openvdb::MetaMap& meta,
                        const std::string& what) {
  AtomicFile output(path);
  std::vector<std::string> names;
  for (const auto& grid : grids) names.push_back(grid->getName());
  try {
    openvdb::io::File file(output.tempPath());
    file.write(grids, meta);
    file.close();
    // libopenvdb's stream reports no write errors (a full disk leaves a short file): the file is
    // walked as a reader would before it may replace the target.
    checkVdbFileStructure(output.tempPath(), names);
  } catch (const std::bad_alloc&) {
    throw;  // out of memory, not of disk: the command says what lowers the need
  } catch (const std::exception& e) {
    throw Error(path + ": cannot write " + what + " (disk full?): " + e.what());
  }
  output.commit();
}

void checkSceneGridTransforms(const openvdb::GridBase& tsdf, const std::vector<const openvdb::GridBase*>& others,
                              const std::string& path) {
  const openvdb::math::Transform& t = tsdf.transform();
  const openvdb::Vec3d v = t.voxelSize();
  const bool uniform = std::isfinite(v[0]) && v[0] >= 1e-5 && v[0] <= 10.0 &&
                       std::fabs(v[1] - v[0]) <= 1e-6 * v[0] && std::fabs(v[2] - v[0]) <= 1e-6 * v[0];
  const std::string map = t.mapType();
  const bool scale_only = map == "UniformScaleMap" || map == "UniformScaleTranslateMap" || map == "ScaleMap" ||
                          map == "ScaleTranslateMap";
  if (!scale_only || !uniform)
    throw Error(path + ": grid 'tsdf' has a voxel of " + std::to_string(v[0]) + " x " + std::to_string(v[1]) + " x " +
                std::to_string(v[2]) + " m in a " + t.mapType() +
                " transform; a scene needs cubic voxels of 10 um to 10 m, unrotated (a damaged or crafted file)");
  for (const openvdb::GridBase* other : others)
    if (other && other->transform() != t)
      throw Error(path + ": grid '" + other->getName() + "' is not in the frame of grid 'tsdf' (a damaged or crafted file)");
}

SceneMetadata sceneMetadataFromFile(const openvdb::MetaMap& meta, const openvdb::GridBase& tsdf,
                                    float fallback_truncation_m, const std::string& path) {
  SceneMetadata m;
  const double grid_voxel_m = tsdf.voxelSize()[0];
  m.voxel_size_m = float(grid_voxel_m);
  m.truncation_m = fallback_truncation_m;
  if (auto v = meta.getMetadata<openvdb::FloatMetadata>(kMetaVoxelSize)) m.voxel_size_m = v->value();
  if (auto v = meta.getMetadata<openvdb::FloatMetadata>(kMetaTruncation)) m.truncation_m = v->value();
  if (auto v = meta.getMetadata<openvdb::StringMetadata>(kMetaClasses)) m.classes = classesFromJson(v->value(), path);
  if (auto v = meta.getMetadata<openvdb::StringMetadata>(kMetaSource)) m.source = v->value();
  if (auto v = meta.getMetadata<openvdb::Int32Metadata>(kMetaFrameCount)) m.frame_count = v->value();
  if (auto v = meta.getMetadata<openvdb::StringMetadata>(kMetaVersion)) m.software_version = v->value();
  readFrameMeta(meta, m, path);
  if (auto v = meta.getMetadata<openvdb::StringMetadata>(kMetaTrajectory)) m.trajectory_tum = v->value();
  if (auto v = meta.getMetadata<openvdb::StringMetadata>(kMetaSourceOptions)) m.source_options_json = v->value();
  if (!(std::isfinite(m.voxel_size_m) && std::fabs(m.voxel_size_m - float(grid_voxel_m)) <= 1e-4f * m.voxel_size_m))
    throw Error(path + ": metadata voxel size " + std::to_string(m.voxel_size_m) + " m contradicts the grid's " +
                std::to_string(grid_voxel_m) + " m (a damaged or crafted file)");
  if (!(std::isfinite(m.truncation_m) && m.truncation_m >= 0 && m.truncation_m < 1e3f * m.voxel_size_m))
    throw Error(path + ": truncation " + std::to_string(m.truncation_m) + " m is not a distance of at most "
                "1000 voxels (a damaged or crafted file)");
  return m;
}

Scene readScene(const std::string& path) {
  ensureOpenVdbInitialized();
  if (!fs::exists(path)) throw Error(noSuchPathMessage(path, "scene file"));
  const std::vector<std::string> names = {kTsdfGridName, kWeightGridName, kColorGridName, kClassGridName,
                                          kClassConfidenceGridName};
  // libopenvdb allocates whatever sizes a file states; the check bounds them by the file's size.
  checkVdbFileStructure(path, names);
  std::vector<std::string> present;
  openvdb::MetaMap::Ptr meta;
  const auto unreadable = [&path](const std::exception& e) {
    return Error(path + ": not a readable OpenVDB file (truncated or foreign?): " + e.what());
  };
  try {
    openvdb::io::File file(path);
    file.open(/*delayLoad=*/false);
    // Only the grids checked above: anything else a tool added to the file stays unread.
    for (const std::string& name : names)
      if (file.hasGrid(name)) present.push_back(name);
    meta = file.getMetadata();
    file.close();
  } catch (const std::exception& e) {
    throw unreadable(e);
  }
  // The grids side by side, each through a file of its own (a File's stream is not shared
  // between threads). Most of the time goes to decompressing and allocating leaves, which
  // libopenvdb does one grid at a time: `info` on a 40 M voxel room took 6.3 s read in turn.
  openvdb::GridPtrVec grids(present.size());
  std::vector<std::string> errors(present.size());
  tbb::parallel_for(size_t(0), present.size(), [&](size_t i) {
    try {
      openvdb::io::File file(path);
      file.open(/*delayLoad=*/false);
      grids[i] = file.readGrid(present[i]);
      file.close();
    } catch (const std::exception& e) {
      errors[i] = e.what();
    }
  });
  for (const std::string& what : errors)
    if (!what.empty()) throw unreadable(std::runtime_error(what));
  Scene scene;
  SceneGrids& g = scene.grids();
  g.tsdf = findGrid<openvdb::FloatGrid>(grids, kTsdfGridName, path, true);
  if (g.tsdf->getGridClass() != openvdb::GRID_LEVEL_SET)
    throw Error(path + ": grid 'tsdf' is not a level set");
  g.weight = findGrid<openvdb::FloatGrid>(grids, kWeightGridName, path, true);
  g.color = findGrid<openvdb::Vec3SGrid>(grids, kColorGridName, path, false);
  g.class_id = findGrid<openvdb::Int32Grid>(grids, kClassGridName, path, false);
  g.class_confidence = findGrid<openvdb::FloatGrid>(grids, kClassConfidenceGridName, path, false);

  checkSceneGridTransforms(*g.tsdf, {g.weight.get(), g.color.get(), g.class_id.get(), g.class_confidence.get()},
                           path);
  scene.meta = sceneMetadataFromFile(*meta, *g.tsdf, g.tsdf->background(), path);
  return scene;
}

}  // namespace vf
