#pragma once
// Surface quality of a reconstruction against a reference mesh, by NICE-SLAM's protocol (Zhu et
// al. 2022, used by the RGB-D SLAM papers since): both surfaces are sampled densely (area-
// weighted points on their triangles), then
//   accuracy    distances from reconstructed points to the reference surface (median, mean),
//   completion  distances from reference points to the reconstructed surface; the completion
//               ratio is the fraction within the threshold,
//   F-score     2 P R / (P + R), P = reconstructed points within the threshold of the
//               reference, R = the completion ratio.
// Only the reference's points a camera saw can count toward completion (markSeen). No OpenVDB.
#include <cstdint>
#include <vector>

#include "core/image.h"
#include "core/intrinsics.h"
#include "core/mesh.h"
#include "core/pose.h"

namespace vf {

double surfaceArea(const TriangleMesh& mesh);

// `count` points on the triangles, uniform on each triangle, each triangle getting its share of
// the area in points (systematic sampling: rounded up or down at random). The same mesh, count
// and seed give the same points on every machine (own integer generator, no std::
// distributions). Throws vf::Error for a mesh without area.
std::vector<Vec3f> sampleSurface(const TriangleMesh& mesh, size_t count, uint64_t seed = 1);

// The mesh with its positions (and normals) moved by T.
TriangleMesh transformMesh(const TriangleMesh& mesh, const Pose& T);

// One camera of a trajectory, in the reference's frame.
struct ViewCamera {
  Pose T_world_cam = Pose::Identity();
  Intrinsics intrinsics;
  float min_depth_m = 0.2f, max_depth_m = 4.f;
  const DepthImage* depth = nullptr;  // the frame's depth (metres), for occlusion; may be null
  float occlusion_tolerance_m = 0.05f;
};

// seen[i] |= point i projects into the image at a depth within [min, max] and, with a depth map,
// has a reading there that it is not behind by more than the tolerance (a point with no
// reading at its pixel was not seen). seen must have points.size() entries.
void markSeen(const std::vector<Vec3f>& points, const ViewCamera& camera, std::vector<uint8_t>& seen);

struct SurfaceMetrics {
  double threshold_m = 0.05;
  size_t reconstruction_points = 0, reference_points = 0;
  double accuracy_median_m = 0, accuracy_mean_m = 0;
  double completion_median_m = 0, completion_mean_m = 0;
  double precision = 0;         // fraction of reconstructed points within the threshold
  double completion_ratio = 0;  // recall: fraction of reference points within the threshold
  double fscore = 0;
};

// From the two sets of distances (infinite ones count as misses and are left out of the means).
// Throws vf::Error when either is empty.
SurfaceMetrics surfaceMetrics(const std::vector<float>& reconstruction_to_reference_m,
                              const std::vector<float>& reference_to_reconstruction_m, double threshold_m);

}  // namespace vf
