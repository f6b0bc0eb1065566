#pragma once
// How much of the room a reconstruction got, and how well:
//   completion  the fraction of the SEEN ground-truth surface within `threshold_m` (3 cm) of the
//               reconstructed triangles. "Seen": a point of the known surface that at least one
//               frame of the path had in its image, within 0.4-4 m depth, at less than 75
//               degrees of incidence and not hidden behind another surface (exact ray casts
//               against the room, no depth map involved). Surface no camera saw cannot be
//               reconstructed and does not count against it.
//   accuracy    distances from the reconstructed vertices to the known surface (exact, from the
//               primitives), their mean, median and 90th percentile, and the fraction within the
//               threshold (precision); F-score = 2 P C / (P + C).
// The reconstruction must be in the room's frame (groundtruth.txt's): alignTo gives the motion.
#include <cstdint>
#include <string>
#include <vector>

#include "core/intrinsics.h"
#include "core/mesh.h"
#include "core/pose.h"
#include "room_geometry.h"

namespace vf::synth {

// Points on a regular grid of `spacing_m` over every face (spheres: a Fibonacci lattice),
// without the points hidden inside another solid (a box's underside on the floor). Grouped in
// patches of nearby points so that a camera can skip a patch out of its view at once.
struct SurfaceSamples {
  struct Patch {
    size_t begin = 0, end = 0;
    Vec3 lo, hi;  // bounds of its points
  };
  std::vector<Vec3> points, normals;
  std::vector<int> primitive;
  std::vector<Patch> patches;
  size_t size() const { return points.size(); }
};
SurfaceSamples sampleSurface(const Room& room, float spacing_m = 0.01f);

struct SeenOptions {
  float min_depth_m = 0.4f, max_depth_m = 4.0f;  // the fusion's default depth range
  float max_incidence_deg = 75.f;                // the sensor gives no reading beyond it
};
// 1 for every sample some camera of `path` saw (intrinsics `k`), else 0.
std::vector<uint8_t> markSeen(const Room& room, const SurfaceSamples& samples, const Trajectory& path,
                              const Intrinsics& k, const SeenOptions& options = {});

// Distance from points to the nearest triangle of a mesh, through a hash of cubic cells: each
// triangle is listed in the cells its bounds meet (near its plane), a query looks at the cells
// within its radius.
class TriangleIndex {
 public:
  // Throws vf::Error when the mesh has no triangles or a triangle names a missing vertex.
  TriangleIndex(const TriangleMesh& mesh, float cell_m);
  // Distance to the nearest triangle when it is at most `radius_m` (<= cell_m), else +inf.
  float nearestWithin(const Vec3& p, float radius_m) const;

 private:
  float cell_m_;
  std::vector<Vec3> a_, b_, c_;  // triangle corners
  std::vector<std::pair<uint64_t, uint32_t>> entries_;  // (cell key, triangle), sorted
};

struct SurfaceScores {
  float threshold_m = 0.03f;
  size_t samples = 0, seen = 0, complete = 0;
  double completion = 0;  // complete / seen
  size_t vertices = 0;
  double accuracy_mean_m = 0, accuracy_median_m = 0, precision = 0, fscore = 0;
  // 90th percentile of the vertices' distances: a wall fused twice a few centimetres apart (a
  // loop closed badly) moves it where the mean and median barely notice.
  double accuracy_p90_m = 0;
  // Per primitive: (seen, complete), for saying which parts are missing.
  std::vector<std::pair<size_t, size_t>> by_primitive;
};
// Throws vf::Error when no sample is seen or the mesh has no triangles.
SurfaceScores scoreReconstruction(const Room& room, const SurfaceSamples& samples, const std::vector<uint8_t>& seen,
                                  const TriangleMesh& reconstruction, float threshold_m = 0.03f);

// How a reconstruction made in its own frame (vdbfuse: the first camera's) is put into the room's.
enum class Alignment { kNone, kFirstPose, kAte };
Alignment parseAlignment(const std::string& name);  // none | first | ate; throws vf::Error otherwise
// T_room_reconstruction from the estimated trajectory and the ground truth: the ATE's rigid
// alignment (Horn), or the first estimated pose onto its ground-truth pose.
Pose alignTo(const Trajectory& estimate, const Trajectory& ground_truth, Alignment alignment);

TriangleMesh transformed(const TriangleMesh& mesh, const Pose& T);

}  // namespace vf::synth
