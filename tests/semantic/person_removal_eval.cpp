// person_removal_eval CAPTURE LABELS_DIR WITH.vdb WITHOUT.vdb [--tolerance-m 0.05] [--person-share 0.5]
//
// How much of the dancer `--dynamic-classes person` removes, and how much static scene it keeps.
// Both scenes must have been fused with `--poses given` (world = the first frame's camera). Each
// scene is meshed (meshScene); every vertex is projected into every frame with the phone's pose
// and the depth intrinsics. The vertex is visible in a frame when it lies on the measured
// surface there (|z - depth| < tolerance); it is a person vertex when it falls inside the
// (undilated) person mask in at least `person-share` of the frames where it is visible (and,
// reported too, in at least one of them), else a static vertex. Vertices never visible are
// counted apart. Prints the counts for both meshes and the two ratios:
//   person kept  = person vertices with / person vertices without    (target <= 5 %)
//   static change = static vertices with / static vertices without - 1  (target within 2 %)
#include <tbb/parallel_for.h>

#include <atomic>
#include <cmath>
#include <cstdio>
#include <cstdlib>
#include <string>
#include <vector>

#include "core/error.h"
#include "io/class_table_io.h"
#include "io/label_maps.h"
#include "io/record3d_export.h"
#include "vdb/mesher.h"
#include "vdb/scene.h"

namespace {

struct Frame {
  vf::DepthImage depth;
  vf::LabelImage labels;
  vf::Pose T_cam_world;
};

struct Counts {
  size_t vertices = 0, unseen = 0, person = 0, person_any = 0, static_ = 0, static_any = 0;
};

Counts classify(const vf::TriangleMesh& mesh, const std::vector<Frame>& frames, const vf::Intrinsics& k,
                float tolerance_m, double person_share, int person_id) {
  std::atomic<size_t> unseen{0}, person{0}, person_any{0};
  tbb::parallel_for(tbb::blocked_range<size_t>(0, mesh.vertexCount()), [&](const tbb::blocked_range<size_t>& r) {
    size_t n_unseen = 0, n_person = 0, n_any = 0;
    for (size_t i = r.begin(); i != r.end(); ++i) {
      const vf::Vec3f p = mesh.positions[i];
      const Eigen::Vector3d pw(p.x, p.y, p.z);
      int visible = 0, inside = 0;
      for (const Frame& f : frames) {
        const Eigen::Vector3d pc = f.T_cam_world * pw;
        if (pc.z() <= 0) continue;
        const int u = int(std::floor(k.fx * pc.x() / pc.z() + k.cx + 0.5));
        const int v = int(std::floor(k.fy * pc.y() / pc.z() + k.cy + 0.5));
        if (u < 0 || v < 0 || u >= k.width || v >= k.height) continue;
        const float d = f.depth(u, v);
        if (d <= 0.f || std::abs(float(pc.z()) - d) >= tolerance_m) continue;
        ++visible;
        if (f.labels(u, v) == person_id) ++inside;
      }
      if (visible == 0) ++n_unseen;
      else {
        if (inside > 0) ++n_any;
        if (double(inside) >= person_share * double(visible)) ++n_person;
      }
    }
    unseen += n_unseen;
    person += n_person;
    person_any += n_any;
  });
  Counts c;
  c.vertices = mesh.vertexCount();
  c.unseen = unseen;
  c.person = person;
  c.person_any = person_any;
  c.static_ = c.vertices - c.unseen - c.person;
  c.static_any = c.vertices - c.unseen - c.person_any;
  return c;
}

}  // namespace

int main(int argc, char** argv) {
  if (argc < 5) {
    std::fprintf(stderr,
                 "usage: %s CAPTURE LABELS_DIR WITH.vdb WITHOUT.vdb [--tolerance-m 0.05] [--person-share 0.5] "
                 "[--min-confidence 2]\n",
                 argv[0]);
    return 2;
  }
  float tolerance_m = 0.05f;
  double person_share = 0.5;
  int min_confidence = 2;
  for (int a = 5; a + 1 < argc; a += 2) {
    const std::string opt = argv[a];
    if (opt == "--tolerance-m") tolerance_m = std::stof(argv[a + 1]);
    else if (opt == "--person-share") person_share = std::stod(argv[a + 1]);
    else if (opt == "--min-confidence") min_confidence = std::atoi(argv[a + 1]);
    else {
      std::fprintf(stderr, "unknown option %s\n", opt.c_str());
      return 2;
    }
  }
  try {
    vf::Record3dOptions options;
    options.min_confidence = min_confidence;
    options.load_color = false;
    const auto source = vf::openRecord3d(argv[1], options);
    const vf::Intrinsics k = source->depthIntrinsics();
    const vf::LabelMapDir labels(argv[2]);
    const vf::ClassTable table = vf::readClassTable(std::string(argv[2]) + "/classes.json");
    const vf::ClassInfo* person = table.findName("person");
    if (!person) throw vf::Error(std::string(argv[2]) + "/classes.json has no class named person");
    std::vector<Frame> frames(size_t(source->size()));
    // The scenes were fused with --poses given: in the phone's own world frame.
    for (int i = 0; i < source->size(); ++i) {
      vf::RgbdFrame f = source->load(i);
      vf::LabelLookup l = labels.load(f.name, f.index, k.width, k.height);
      if (!l.labels) throw vf::Error("label map " + l.path + " not found");
      frames[size_t(i)] = {std::move(f.depth), std::move(*l.labels), f.T_world_cam_given->inverse()};
    }
    Counts c[2];
    for (int s = 0; s < 2; ++s) {
      const vf::Scene scene = vf::readScene(argv[3 + s]);
      const vf::TriangleMesh mesh = vf::meshScene(scene);
      c[s] = classify(mesh, frames, k, tolerance_m, person_share, person->id);
      std::printf("%-8s %s: %zu vertices: %zu person (%zu in the mask in any frame), %zu static, %zu never visible\n",
                  s == 0 ? "with" : "without", argv[3 + s], c[s].vertices, c[s].person, c[s].person_any,
                  c[s].static_, c[s].unseen);
    }
    std::printf("visibility |z - depth| < %.3f m over %zu frames; person = inside the mask in >= %.0f%% of them\n",
                tolerance_m, frames.size(), 100 * person_share);
    std::printf("person vertices kept with the option: %.2f%% (any-frame rule: %.2f%%)\n",
                100.0 * double(c[0].person) / double(std::max<size_t>(1, c[1].person)),
                100.0 * double(c[0].person_any) / double(std::max<size_t>(1, c[1].person_any)));
    std::printf("static vertex count change: %+.2f%% (any-frame rule: %+.2f%%)\n",
                100.0 * (double(c[0].static_) / double(std::max<size_t>(1, c[1].static_)) - 1.0),
                100.0 * (double(c[0].static_any) / double(std::max<size_t>(1, c[1].static_any)) - 1.0));
  } catch (const std::exception& e) {
    std::fprintf(stderr, "error: %s\n", e.what());
    return 1;
  }
  return 0;
}
