#include "viewer/scene_content.h"

#include <algorithm>
#include <chrono>
#include <cmath>
#include <cstdio>
#include <cstdlib>
#include <filesystem>
#include <future>
#include <limits>
#include <map>

#include "core/error.h"
#include "core/text_fields.h"
#include "io/trajectory_io.h"
#include "vdb/mesh_ops.h"
#include "vdb/mesher.h"
#include "vdb/scene_frame.h"
#include "vdb/vertex_color.h"
#include "viewer/view_style.h"
#include "viewer/view_options.h"

namespace vf::viewer {
namespace {

double secondsSince(std::chrono::steady_clock::time_point t0) {
  return std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count();
}

void computeSurfaceBounds(SceneContent& c) {
  const float inf = std::numeric_limits<float>::infinity();
  Vec3f lo{inf, inf, inf}, hi{-inf, -inf, -inf};
  for (const ClassPart& part : c.parts)
    for (const Vec3f& p : part.mesh.positions) {
      lo = {std::min(lo.x, p.x), std::min(lo.y, p.y), std::min(lo.z, p.z)};
      hi = {std::max(hi.x, p.x), std::max(hi.y, p.y), std::max(hi.z, p.z)};
    }
  if (c.triangles == 0) {  // nothing meshed: fall back to the observed voxels
    lo = c.summary.bounds_min_m;
    hi = c.summary.bounds_max_m;
  }
  c.surface_min_m = lo;
  c.surface_max_m = hi;
}

void buildParts(SceneContent& c, TriangleMesh mesh) {
  c.triangles = mesh.triangleCount();
  if (!c.scene.hasClasses()) {
    ClassPart part;
    part.mesh = std::move(mesh);
    c.parts.push_back(std::move(part));
    return;
  }
  // Rows: every class the class grid holds, known ids first, unknown (-1) last so that key 1 is
  // the first real class.
  for (const ClassVoxelCount& count : c.summary.classes)
    c.rows.push_back({count.id, count.name, classColor(c.scene.meta.classes, count.id), count.voxels, 0});
  std::stable_partition(c.rows.begin(), c.rows.end(), [](const ClassRow& r) { return r.id >= 0; });
  std::map<int32_t, TriangleMesh> split = splitByClass(mesh);
  for (auto& [id, part_mesh] : split) {  // a face class the grid count missed still gets a row
    auto row = std::find_if(c.rows.begin(), c.rows.end(), [id = id](const ClassRow& r) { return r.id == id; });
    if (row == c.rows.end())
      c.rows.push_back({id, id < 0 ? "unknown" : "(not in table)", classColor(c.scene.meta.classes, id), 0, 0});
  }
  for (ClassRow& row : c.rows) {
    ClassPart part;
    part.id = row.id;
    auto it = split.find(row.id);
    if (it != split.end()) part.mesh = std::move(it->second);
    row.triangles = part.mesh.triangleCount();
    part.class_colors.assign(part.mesh.vertexCount(), row.color);
    c.parts.push_back(std::move(part));
  }
}

// A camera saw the scene from a few metres: one farther from the surface's box than this did
// not. Framed or drawn, such a pose shrinks the scene to nothing (1e30 m away: a blank picture,
// depth precision spent on the empty distance).
double farthestPlausibleCamera_m(const SceneContent& c) {
  const Vec3f extent = c.surface_max_m - c.surface_min_m;
  return std::max(1000.0, 10.0 * double(norm(extent)));
}

// Throws vf::Error naming `path` and the first pose that no camera of this scene can have had.
void requireCamerasNearScene(const SceneContent& c, const Trajectory& trajectory, const std::string& path) {
  const double limit_m = farthestPlausibleCamera_m(c);
  for (size_t i = 0; i < trajectory.size(); ++i) {
    const Eigen::Vector3d t = trajectory[i].T_world_cam.translation();
    const Eigen::Vector3d lo(c.surface_min_m.x, c.surface_min_m.y, c.surface_min_m.z),
        hi(c.surface_max_m.x, c.surface_max_m.y, c.surface_max_m.z);
    const double away_m = (t.cwiseMax(lo).cwiseMin(hi) - t).norm();  // 0 inside the box
    if (std::isfinite(away_m) && away_m <= limit_m) continue;
    char text[200];
    std::snprintf(text, sizeof text, "pose %zu is at (%.4g, %.4g, %.4g) m, %.3g m from the scene's surface (at most "
                  "%.0f m for a camera that saw it): not this scene's trajectory",
                  i, t.x(), t.y(), t.z(), away_m, limit_m);
    throw Error(path + ": " + text);
  }
}

void loadTrajectory(SceneContent& c, const std::string& path, bool load) {
  if (!load) return;
  if (!path.empty()) {  // asked for by name: failing to read it is an error
    c.trajectory = readTumTrajectory(path);
    requireCamerasNearScene(c, c.trajectory, path);
    c.trajectory_path = path;
    return;
  }
  const std::string beside = defaultTrajectoryPath(c.scene_path);
  if (!std::filesystem::exists(beside)) {
    c.notices.push_back("no trajectory beside the scene (" + beside + "); --trajectory FILE names one");
    return;
  }
  try {
    Trajectory trajectory = readTumTrajectory(beside);
    requireCamerasNearScene(c, trajectory, beside);
    c.trajectory = std::move(trajectory);
    c.trajectory_path = beside;
  } catch (const Error& e) {  // a stray .txt beside the scene should not stop the viewer
    c.notices.push_back(std::string("trajectory not shown: ") + e.what());
  }
}

// Up and forward as recorded; for a scene written before they were, estimated from the
// trajectory and a quarter of the surface's vertices (the same estimate exports make).
void computeLevelFrame(SceneContent& c) {
  std::vector<const TriangleMesh*> surface;
  for (const ClassPart& part : c.parts) surface.push_back(&part.mesh);
  const SceneMetadata& m = c.scene.meta;
  if (norm(m.up_world) > 0 && norm(m.forward_world) > 0) {
    c.frame = levelFrame(m.up_world, m.forward_world, surface);
    c.frame.up_source = m.up_source;
    return;
  }
  TriangleMesh samples;
  for (const TriangleMesh* mesh : surface)
    if (mesh->hasNormals())
      for (size_t i = 0; i < mesh->positions.size(); i += 4) {
        samples.positions.push_back(mesh->positions[i]);
        samples.normals.push_back(mesh->normals[i]);
      }
  const SceneUp up = estimateSceneUp(c.trajectory, samples);
  c.frame = levelFrame(up.up, up.forward, surface);
  c.frame.up_source = up.source + " (estimated: the scene does not record up)";
  c.notices.push_back("up: the scene does not record it; estimated from the " + up.source + " (" + up.detail + ")");
}

}  // namespace

Rgb8 visibleOnBackdrop(Rgb8 c) {
  const double luma = 0.2126 * c.r + 0.7152 * c.g + 0.0722 * c.b;
  if (luma >= kMinClassLuma) return c;
  const double k = (kMinClassLuma - luma) / (255.0 - luma);  // towards white until the luma is reached
  auto lift = [k](uint8_t v) { return uint8_t(std::lround(v + (255.0 - v) * k)); };
  return {lift(c.r), lift(c.g), lift(c.b), c.a};
}

Rgb8 classColor(const ClassTable& table, int id) { return visibleOnBackdrop(classColorOf(table, id)); }

SceneContent loadSceneContent(const std::string& scene_path, const std::string& trajectory_path,
                              bool load_trajectory, float min_weight) {
  SceneContent c;
  c.scene_path = scene_path;
  auto t0 = std::chrono::steady_clock::now();
  c.scene = readScene(scene_path);
  c.read_s = secondsSince(t0);
  if (c.scene.activeVoxelCount() == 0)
    throw Error(scene_path + ": the scene is empty (no observed voxel), nothing to show; was it fused from frames "
                             "that saw nothing inside the volume?");
  t0 = std::chrono::steady_clock::now();
  // The summary (class voxel counts: one serial pass over the voxels) runs beside the parallel
  // mesher; both only read the grids.
  std::future<SceneSummary> summary = std::async(std::launch::async, [&c] { return summarizeScene(c.scene); });
  MeshOptions options;
  options.min_weight = min_weight;
  TriangleMesh mesh = meshScene(c.scene, options);
  c.summary = summary.get();
  c.mesh_s = secondsSince(t0);
  t0 = std::chrono::steady_clock::now();
  buildParts(c, std::move(mesh));
  computeSurfaceBounds(c);
  c.split_s = secondsSince(t0);
  loadTrajectory(c, trajectory_path, load_trajectory);
  computeLevelFrame(c);
  return c;
}

int findClassRow(const std::vector<ClassRow>& rows, const std::string& key) {
  for (size_t i = 0; i < rows.size(); ++i)
    if (rows[i].name == key) return int(i);
  int id = 0;
  if (!parseInt(key, id)) return -1;
  for (size_t i = 0; i < rows.size(); ++i)
    if (rows[i].id == id) return int(i);
  return -1;
}

TriangleMesh mergeMeshes(const std::vector<const TriangleMesh*>& meshes) {
  TriangleMesh out;
  bool normals = true, colors = true, classes = true;
  size_t vertices = 0, triangles = 0;
  for (const TriangleMesh* m : meshes) {
    normals &= m->hasNormals() || m->vertexCount() == 0;
    colors &= m->hasColors() || m->vertexCount() == 0;
    classes &= m->hasClasses() || m->vertexCount() == 0;
    vertices += m->vertexCount();
    triangles += m->triangleCount();
  }
  out.positions.reserve(vertices);
  out.triangles.reserve(triangles);
  for (const TriangleMesh* m : meshes) {
    const int32_t base = int32_t(out.positions.size());
    out.positions.insert(out.positions.end(), m->positions.begin(), m->positions.end());
    if (normals) out.normals.insert(out.normals.end(), m->normals.begin(), m->normals.end());
    if (colors) out.colors.insert(out.colors.end(), m->colors.begin(), m->colors.end());
    if (classes) out.classes.insert(out.classes.end(), m->classes.begin(), m->classes.end());
    for (const auto& t : m->triangles) out.triangles.push_back({t[0] + base, t[1] + base, t[2] + base});
  }
  if (out.positions.empty()) out.normals.clear(), out.colors.clear(), out.classes.clear();
  return out;
}

}  // namespace vf::viewer
