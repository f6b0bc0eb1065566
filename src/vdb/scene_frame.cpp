#include "vdb/scene_frame.h"

#include <Eigen/Eigenvalues>

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <functional>
#include <map>

#include "core/error.h"
#include "vdb/brick_surface.h"
#include "vdb/scene_export.h"

namespace vf {
namespace {

Eigen::Vector3d toEigen(Vec3f v) { return {v.x, v.y, v.z}; }
Vec3f toVec(const Eigen::Vector3d& v) { return {float(v.x()), float(v.y()), float(v.z())}; }

// The part of `v` perpendicular to the unit `up`, normalised; zero when v is (nearly) along up.
Vec3f horizontal(Vec3f v, Vec3f up) {
  const Vec3f h = v - up * dot(v, up);
  return norm(h) > 0.1f * norm(v) ? normalized(h) : Vec3f{0, 0, 0};
}

// A heading for `up`: the first camera's view direction made horizontal, else the mean view
// direction's, else the world axis least along up.
Vec3f headingFor(Vec3f up, const Trajectory& traj) {
  if (!traj.empty()) {
    const Vec3f first = horizontal(toVec(traj.front().T_world_cam.linear().col(2)), up);
    if (norm(first) > 0) return first;
    Eigen::Vector3d mean = Eigen::Vector3d::Zero();
    for (const StampedPose& p : traj) mean += p.T_world_cam.linear().col(2);
    const Vec3f m = horizontal(toVec(mean), up);
    if (norm(m) > 0) return m;
  } else {
    const Vec3f z = horizontal({0, 0, 1}, up);
    if (norm(z) > 0) return z;
  }
  const Vec3f axes[3] = {{1, 0, 0}, {0, 1, 0}, {0, 0, 1}};
  Vec3f best = axes[0];
  for (const Vec3f& a : axes)
    if (std::fabs(dot(a, up)) < std::fabs(dot(best, up))) best = a;
  return horizontal(best, up);
}

float cosDeg(float deg) { return std::cos(deg * float(M_PI) / 180.f); }

// Mean shift on the unit sphere: the mean of the normals within 12 degrees, until it settles.
Vec3f settle(const std::vector<Vec3f>& normals, Vec3f u) {
  for (int iter = 0; iter < 20; ++iter) {
    Vec3f sum{0, 0, 0};
    for (const Vec3f& n : normals)
      if (dot(n, u) > cosDeg(12.f)) sum = sum + n;
    if (norm(sum) == 0) return u;
    const Vec3f next = normalized(sum);
    if (dot(next, u) > cosDeg(0.05f)) return next;
    u = next;
  }
  return u;
}

// Directions that many surface normals share (floors and table tops, walls, flat objects):
// the modes of the normals within 65 degrees of the cameras' mean up, by mean shift from seeds
// spread over them, nearest that up first. Nearest, not strongest: a camera pitched down by p
// sees the floor's normal p from its up; what holds more surface may be a rounded object.
std::vector<Vec3f> normalModes(const TriangleMesh& s, Vec3f camera_up) {
  std::vector<Vec3f> normals;
  const size_t stride = std::max<size_t>(1, s.normals.size() / 50000);  // plenty for a direction
  for (size_t i = 0; i < s.normals.size(); i += stride)
    if (dot(s.normals[i], camera_up) > cosDeg(65.f)) normals.push_back(s.normals[i]);
  std::vector<Vec3f> modes;
  if (normals.empty()) return modes;
  const size_t seeds = 48, step = std::max<size_t>(1, normals.size() / seeds);
  for (size_t k = 0; k <= normals.size(); k += step) {
    const Vec3f u = settle(normals, k < normals.size() ? normals[k] : camera_up);
    if (std::none_of(modes.begin(), modes.end(), [&](const Vec3f& m) { return dot(m, u) > cosDeg(5.f); }))
      modes.push_back(u);
  }
  std::sort(modes.begin(), modes.end(), [&](Vec3f a, Vec3f b) { return dot(a, camera_up) > dot(b, camera_up); });
  return modes;
}

struct Plane {
  Vec3f normal{0, 0, 0};
  float height_m = 0;  // along the normal
  size_t support = 0;  // samples on it
};

// The most populated slab, 6 cm thick, of the samples facing `u` (within 20 degrees: normals
// from TSDF differences are noisy at fine voxels), refined by a least-squares plane through its
// points; none when those points are not flat.
Plane dominantPlane(const TriangleMesh& s, Vec3f u) {
  const float bin_m = 0.02f, c = cosDeg(20.f);
  std::map<long, size_t> bins;
  for (size_t i = 0; i < s.positions.size(); ++i)
    if (dot(s.normals[i], u) > c) ++bins[std::lround(std::floor(dot(s.positions[i], u) / bin_m))];
  Plane best;
  long best_bin = 0;
  for (const auto& [bin, count] : bins) {
    const size_t around = count + (bins.count(bin - 1) ? bins[bin - 1] : 0) + (bins.count(bin + 1) ? bins[bin + 1] : 0);
    if (around > best.support) best.support = around, best_bin = bin;
  }
  if (best.support == 0) return best;
  const float lo = (float(best_bin) - 1.f) * bin_m, hi = (float(best_bin) + 2.f) * bin_m;
  Eigen::Vector3d mean = Eigen::Vector3d::Zero();
  std::vector<Eigen::Vector3d> pts;
  for (size_t i = 0; i < s.positions.size(); ++i) {
    const float h = dot(s.positions[i], u);
    if (h >= lo && h < hi && dot(s.normals[i], u) > c) pts.push_back(toEigen(s.positions[i])), mean += pts.back();
  }
  mean /= double(pts.size());
  Eigen::Matrix3d cov = Eigen::Matrix3d::Zero();
  for (const auto& p : pts) cov += (p - mean) * (p - mean).transpose();
  const Eigen::SelfAdjointEigenSolver<Eigen::Matrix3d> eig(cov);
  Vec3f n = normalized(toVec(eig.eigenvectors().col(0)));  // smallest eigenvalue first
  if (dot(n, u) < 0) n = -n;
  // A slab that is not flat (an object's rounded top) has no clear smallest direction.
  if (dot(n, u) < cosDeg(10.f) || eig.eigenvalues()(0) > 0.1 * eig.eigenvalues()(1)) return {};
  best.normal = n;
  best.height_m = float(toEigen(n).dot(mean));
  best.support = pts.size();
  return best;
}

SceneUp withHeading(SceneUp up, const Trajectory& traj) {
  up.forward = headingFor(up.up, traj);
  return up;
}

}  // namespace

Vec3f recordedUpInFusedFrame(Vec3f up_recorded, const Pose& T_recorded_cam0, const Pose& T_fused_cam0) {
  // R_fused_recorded = R_fused_cam0 * R_recorded_cam0^-1: the same camera seen from both frames.
  const Eigen::Matrix3d r = T_fused_cam0.linear() * T_recorded_cam0.linear().transpose();
  return normalized(toVec(r * toEigen(up_recorded)));
}

SceneUp estimateSceneUp(const Trajectory& traj, const TriangleMesh& surface, const std::optional<Vec3f>& recorded_up) {
  if (recorded_up && norm(*recorded_up) > 0) {
    SceneUp up;
    up.up = normalized(*recorded_up);
    up.source = kUpFromRecordedPoses;
    up.detail = "gravity as the device recorded it";
    return withHeading(up, traj);
  }
  // The cameras' mean up-vector: people hold cameras roughly level, pitched maybe 20-45 degrees.
  Eigen::Vector3d mean_up = Eigen::Vector3d::Zero();
  for (const StampedPose& p : traj) mean_up -= p.T_world_cam.linear().col(1);
  const Vec3f camera_up = traj.empty() || mean_up.norm() == 0 ? Vec3f{0, -1, 0} : normalized(toVec(mean_up));

  const bool has_normals = surface.hasNormals() && surface.normals.size() == surface.positions.size();
  for (const Vec3f& mode : has_normals ? normalModes(surface, camera_up) : std::vector<Vec3f>{}) {
    Plane plane = dominantPlane(surface, mode);
    if (norm(plane.normal) == 0) continue;
    // Once more around the fitted normal: the slab then follows the plane across the whole room.
    if (const Plane again = dominantPlane(surface, plane.normal); norm(again.normal) > 0) plane = again;
    // "Below the cameras": a floor or table the cameras looked down on, not a ceiling or shelf.
    std::vector<float> heights;
    for (const StampedPose& p : traj) heights.push_back(dot(toVec(p.T_world_cam.translation()), plane.normal));
    std::nth_element(heights.begin(), heights.begin() + heights.size() / 2, heights.end());
    const bool below = heights.empty() || plane.height_m < heights[heights.size() / 2] - 0.1f;
    const size_t needed = std::max<size_t>(200, surface.positions.size() / 50);  // 2 % of the surface
    const float tilt_deg = std::acos(std::clamp(dot(plane.normal, camera_up), -1.f, 1.f)) * 180.f / float(M_PI);
    if (below && plane.support >= needed && tilt_deg < 60.f) {
      SceneUp up;
      up.up = plane.normal;
      up.source = kUpFromFloorPlane;
      char text[200];
      std::snprintf(text, sizeof text, "%.0f%% of the surface samples on one plane, %.2f m below the cameras' median; "
                    "%.0f degrees from the cameras' mean up", 100.0 * double(plane.support) / double(surface.positions.size()),
                    heights.empty() ? 0.0 : double(heights[heights.size() / 2] - plane.height_m), double(tilt_deg));
      up.detail = text;
      return withHeading(up, traj);
    }
  }
  SceneUp up;
  up.up = camera_up;
  up.source = kUpFromCameraUp;
  up.detail = traj.empty() ? "no trajectory: the first camera's -y" : "mean image -y axis of " + std::to_string(traj.size()) + " cameras";
  return withHeading(up, traj);
}

namespace {

// One sample in this many is plenty to find a floor (2 % of the samples must lie on it) and
// keeps a room's samples to tens of megabytes.
constexpr int kUpSamplesKeepOneIn = 4;

SceneUp setFrame(SceneMetadata& meta, const Trajectory& trajectory, const std::optional<Vec3f>& recorded,
                 const std::function<TriangleMesh()>& surface) {
  const SceneUp up = recorded ? estimateSceneUp(trajectory, TriangleMesh{}, recorded)
                              : estimateSceneUp(trajectory, surface(), std::nullopt);
  meta.up_world = up.up;
  meta.forward_world = up.forward;
  meta.up_source = up.source;
  return up;
}

// The recorded world's up in the fused frame, when the source knows gravity.
std::optional<Vec3f> recordedUp(const Trajectory& trajectory, const FrameSource& source) {
  if (const std::optional<Vec3f> world_up = source.worldUp(); world_up && !trajectory.empty() && source.size() > 0) {
    const RgbdFrame first = source.load(0);
    if (first.T_world_cam_given)
      return recordedUpInFusedFrame(*world_up, *first.T_world_cam_given, trajectory.front().T_world_cam);
  }
  return std::nullopt;
}

}  // namespace

SceneUp setSceneFrame(Scene& scene, const Trajectory& trajectory, const FrameSource& source) {
  scene.meta.depth_intrinsics = source.depthIntrinsics();
  return setFrame(scene.meta, trajectory, recordedUp(trajectory, source), [&] { return scenePointCloud(scene); });
}

SceneUp setSceneFrame(SceneMetadata& meta, const BrickVolumeView& bricks, const Trajectory& trajectory,
                      const FrameSource& source) {
  meta.depth_intrinsics = source.depthIntrinsics();
  return setFrame(meta, trajectory, recordedUp(trajectory, source),
                  [&] { return brickSurfaceSamples(bricks, kUpSamplesKeepOneIn); });
}

SceneUp setSceneFrame(Scene& scene, const Trajectory& trajectory) {
  return setFrame(scene.meta, trajectory, std::nullopt, [&] { return scenePointCloud(scene); });
}

SceneAxes parseSceneAxes(const std::string& text) {
  if (text == "camera") return SceneAxes::kCamera;
  if (text == "z-up") return SceneAxes::kZUp;
  if (text == "y-up") return SceneAxes::kYUp;
  throw Error("axes '" + text + "': expected camera (as fused), z-up (Blender, PLY) or y-up (glTF, OBJ)");
}

const char* sceneAxesName(SceneAxes axes) {
  return axes == SceneAxes::kCamera ? "camera" : axes == SceneAxes::kZUp ? "z-up" : "y-up";
}

Rigid3f exportRotation(const SceneMetadata& meta, SceneAxes axes) {
  Rigid3f r = Rigid3f::identity();
  if (axes == SceneAxes::kCamera) return r;
  const bool known = norm(meta.up_world) > 0 && norm(meta.forward_world) > 0;
  const Vec3f up = known ? meta.up_world : Vec3f{0, -1, 0};
  const Vec3f fwd = known ? meta.forward_world : Vec3f{0, 0, 1};
  const Vec3f right = cross(fwd, up);  // camera right = forward x up
  // Rows: the export axes written in scene coordinates.
  const Vec3f rows[3] = {right, axes == SceneAxes::kZUp ? fwd : up, axes == SceneAxes::kZUp ? up : -fwd};
  for (int i = 0; i < 3; ++i) {
    r.r[i * 3 + 0] = rows[i].x;
    r.r[i * 3 + 1] = rows[i].y;
    r.r[i * 3 + 2] = rows[i].z;
  }
  return r;
}

void transformMesh(TriangleMesh& mesh, const Rigid3f& T) {
  for (Vec3f& p : mesh.positions) p = T * p;
  for (Vec3f& n : mesh.normals) n = T.rotate(n);
}

}  // namespace vf
