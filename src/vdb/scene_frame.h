#pragma once
// Which way is up in a scene, and the frames exports are written in.
//
// Fusion works in the first camera's frame (x right, y down, z forward) or, with recorded poses,
// in the device's. The .vdb keeps that frame; its metadata says where gravity's "up" lies in it
// (SceneMetadata::up_world, forward_world, up_source), and every exporter rotates by it:
// Z-up for Blender and PLY, Y-up with -Z forward for glTF and OBJ, whose importers turn Y-up
// into Blender's Z-up. Only rotations: distances and the origin stay those of the scene.
#include <optional>
#include <string>

#include "core/frame.h"
#include "core/mesh.h"
#include "core/pose.h"
#include "vdb/scene.h"

namespace vf {

// How up was found (SceneMetadata::up_source).
inline constexpr const char* kUpFromRecordedPoses = "recorded poses";  // the device's gravity (ARKit)
inline constexpr const char* kUpFromFloorPlane = "floor plane";        // a large horizontal plane below the cameras
inline constexpr const char* kUpFromCameraUp = "camera up-vectors";    // the cameras' mean image -y axis

struct SceneUp {
  Vec3f up{0, 0, 0};       // unit, scene (fusion world) coordinates
  Vec3f forward{0, 0, 0};  // unit, perpendicular to up: the first camera's heading
  std::string source;      // one of the kUpFrom* names
  std::string detail;      // for people: what the estimate rests on
};

// The recorded world's up, carried into the fused frame: `up_recorded` is in the frame of the
// recorded poses, T_recorded_cam0 the recorded pose of frame 0 and T_fused_cam0 the fused one
// (trajectory[0]), so that whichever frame fusion works in, the same gravity comes out.
Vec3f recordedUpInFusedFrame(Vec3f up_recorded, const Pose& T_recorded_cam0, const Pose& T_fused_cam0);

// Up for a scene:
// - `recorded_up` (already in the fused frame) when the device knew gravity;
// - else the dominant horizontal plane below the cameras, searched from the cameras' mean
//   up-vector (image -y of each T_world_cam) through the surface normals, when it holds enough
//   of the surface (floor, table tops: all parallel);
// - else the cameras' mean up-vector.
// `surface` needs positions and normals (a point cloud or mesh vertices: equal-area samples).
// An empty trajectory stands for the first camera alone (up = -y, forward = +z).
SceneUp estimateSceneUp(const Trajectory& T_world_cam, const TriangleMesh& surface,
                        const std::optional<Vec3f>& recorded_up = std::nullopt);

// For reconstruct: records the source's depth camera and the scene's up (estimateSceneUp on
// the scene's surface points; the source's worldUp() when it has one) in scene.meta.
SceneUp setSceneFrame(Scene& scene, const Trajectory& trajectory, const FrameSource& source);
// The same from the fused bricks, into `meta`, without the scene's grids (a room's would take
// more memory than its bricks): the surface is a hash-picked quarter of brickSurfaceSamples.
SceneUp setSceneFrame(SceneMetadata& meta, const BrickVolumeView& bricks, const Trajectory& trajectory,
                      const FrameSource& source);
// The same without a source (export of a scene written before up was recorded).
SceneUp setSceneFrame(Scene& scene, const Trajectory& trajectory);

enum class SceneAxes { kCamera, kZUp, kYUp };
// "camera", "z-up" or "y-up"; throws vf::Error naming the value.
SceneAxes parseSceneAxes(const std::string& text);
const char* sceneAxesName(SceneAxes axes);

// Rotation from scene coordinates into the export frame (t = 0). kZUp: up -> +Z, forward -> +Y,
// so Blender's front view looks the way the first camera did; kYUp: up -> +Y, forward -> -Z
// (glTF, and Blender's OBJ importer defaults). A scene without up metadata is taken as seen by
// its first camera (up = -y, forward = +z).
Rigid3f exportRotation(const SceneMetadata& meta, SceneAxes axes);

// Positions and normals rotated (and translated) by `T`.
void transformMesh(TriangleMesh& mesh, const Rigid3f& T);

}  // namespace vf
