// phone_trajectory CAPTURE OUT.txt [--max-frames N]: writes the phone's (ARKit) poses as a TUM
// trajectory in the frame `vdbfuse reconstruct` uses (relative to the first frame), so that
//   vdbfuse evaluate -t estimate.txt -g OUT.txt
// gives the ATE of a reconstruction's trajectory against the phone.
#include <cstdio>
#include <cstdlib>
#include <string>

#include "core/error.h"
#include "io/record3d_export.h"
#include "io/trajectory_io.h"

int main(int argc, char** argv) {
  if (argc != 3 && !(argc == 5 && std::string(argv[3]) == "--max-frames")) {
    std::fprintf(stderr, "usage: %s CAPTURE.r3d|EXPORT_DIR OUT.txt [--max-frames N]\n", argv[0]);
    return 2;
  }
  try {
    vf::Record3dOptions options;
    options.load_color = false;
    const auto source = vf::openRecord3d(argv[1], options);
    const int frames = argc == 5 ? std::min(std::atoi(argv[4]), source->size()) : source->size();
    vf::Trajectory trajectory;
    vf::Pose first_inverse = vf::Pose::Identity();
    for (int i = 0; i < frames; ++i) {
      const vf::RgbdFrame f = source->load(i);
      if (!f.T_world_cam_given) throw vf::Error(std::string(argv[1]) + ": frame " + std::to_string(i) + " has no pose");
      if (i == 0) first_inverse = f.T_world_cam_given->inverse();
      trajectory.push_back({f.timestamp, first_inverse * *f.T_world_cam_given});
    }
    vf::writeTumTrajectory(argv[2], trajectory);
    std::printf("wrote %d phone poses to %s\n", frames, argv[2]);
  } catch (const std::exception& e) {
    std::fprintf(stderr, "error: %s\n", e.what());
    return 1;
  }
  return 0;
}
