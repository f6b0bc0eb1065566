#include "vdb/scene_export.h"

#include <openvdb/io/File.h>
#include <openvdb/tools/LevelSetUtil.h>

#include <cmath>

#include "core/error.h"
#include "vdb/scene_grids.h"

namespace vf {

void writeBlenderVolume(const Scene& scene, const std::string& path) {
  ensureOpenVdbInitialized();
  const SceneGrids& g = scene.grids();
  openvdb::FloatGrid::Ptr density = g.tsdf->deepCopy();
  openvdb::tools::sdfToFogVolume(*density);
  density->setName("density");
  openvdb::GridPtrVec grids{density};
  if (g.color) {
    openvdb::Vec3SGrid::Ptr color = g.color->deepCopy();
    color->setName("color");
    grids.push_back(color);
  }
  writeVdbFileAtomic(path, grids, openvdb::MetaMap(), "Blender volume");
}

std::vector<std::string> vdbGridNames(const std::string& path) {
  ensureOpenVdbInitialized();
  std::vector<std::string> names;
  try {
    openvdb::io::File file(path);
    file.open(false);
    for (auto it = file.beginName(); it != file.endName(); ++it) names.push_back(it.gridName());
    file.close();
  } catch (const std::exception& e) {
    throw Error(path + ": not a readable OpenVDB file: " + e.what());
  }
  return names;
}

TriangleMesh scenePointCloud(const Scene& scene, const MeshOptions& options) {
  ensureOpenVdbInitialized();
  const SceneGrids& g = scene.grids();
  const openvdb::FloatTree& tsdf = g.tsdf->tree();
  const openvdb::FloatTree& weight = g.weight->tree();
  const openvdb::math::Transform& xform = g.tsdf->transform();
  const double voxel = xform.voxelSize()[0];
  auto observed = [&](const openvdb::Coord& c, float& v) {
    return tsdf.probeValue(c, v) && (options.min_weight <= 0 || weight.getValue(c) >= options.min_weight);
  };
  TriangleMesh cloud;
  for (auto it = g.tsdf->cbeginValueOn(); it; ++it) {
    const openvdb::Coord ijk = it.getCoord();
    const float v = *it;
    if (options.min_weight > 0 && weight.getValue(ijk) < options.min_weight) continue;
    bool crossing = false;
    openvdb::Vec3d grad(0.0);
    for (int a = 0; a < 3; ++a) {
      openvdb::Coord lo = ijk, hi = ijk;
      lo[a] -= 1;
      hi[a] += 1;
      float vl, vh;
      const bool ol = observed(lo, vl), oh = observed(hi, vh);
      for (int s = 0; s < 2; ++s) {
        const bool o = s ? oh : ol;
        const float n = s ? vh : vl;
        if (o && (n < 0) != (v < 0) && std::fabs(v) <= std::fabs(n)) crossing = true;
      }
      grad[a] = ol && oh ? (vh - vl) / (2 * voxel) : oh ? (vh - v) / voxel : ol ? (v - vl) / voxel : 0.0;
    }
    if (!crossing) continue;
    const double len = grad.length();
    const openvdb::Vec3d nrm = len > 0 ? grad / len : openvdb::Vec3d(0, 0, 1);
    const openvdb::Vec3d p = xform.indexToWorld(ijk) - nrm * double(v);
    cloud.positions.push_back({float(p.x()), float(p.y()), float(p.z())});
    cloud.normals.push_back({float(nrm.x()), float(nrm.y()), float(nrm.z())});
    const int cls = g.class_id ? g.class_id->tree().getValue(ijk) : kSceneUnknownClass;
    if (g.class_id) cloud.classes.push_back(cls);
    Rgb8 col{200, 200, 200, 255};
    if (options.color == MeshColorMode::kClass) {
      const ClassInfo* info = scene.meta.classes.findId(cls);
      col = info ? info->color : Rgb8{128, 128, 128, 255};
    } else if (g.color) {
      const openvdb::Vec3s c = g.color->tree().getValue(ijk);
      auto srgb = [](float x) {
        x = std::clamp(x, 0.f, 1.f);
        const float s = x <= 0.0031308f ? 12.92f * x : 1.055f * std::pow(x, 1.f / 2.4f) - 0.055f;
        return uint8_t(std::lround(s * 255.f));
      };
      col = {srgb(c.x()), srgb(c.y()), srgb(c.z()), 255};
    }
    cloud.colors.push_back(col);
  }
  return cloud;
}

}  // namespace vf
