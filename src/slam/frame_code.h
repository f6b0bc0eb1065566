#pragma once
// A compact appearance code of a frame, for finding the keyframes that saw the same place
// (relocalisation, loop candidates): random ferns on a small thumbnail of depth and intensity,
// as in Glocker et al. 2013 ("Real-time RGB-D camera relocalization") and InfiniTAM v3. Each fern
// is a few binary tests "is this thumbnail pixel's depth (or grey level) below t?"; two frames
// that saw the same place from nearly the same pose answer most ferns alike.
#include <cstdint>
#include <vector>

#include "core/frame.h"

namespace vf::slam {

struct FrameCode {
  std::vector<uint8_t> ferns;  // one value per fern, its tests' answers as bits
  bool empty() const { return ferns.empty(); }
};

class FernEncoder {
 public:
  static constexpr int kThumbWidth = 40, kThumbHeight = 30;
  static constexpr int kFerns = 500, kTestsPerFern = 4;

  // The tests are drawn once from a fixed seed: every run codes frames alike.
  FernEncoder();
  // Empty when too little of the frame has depth to say where it is.
  FrameCode encode(const RgbdFrame& frame, float min_depth_m, float max_depth_m) const;
  // Share of ferns (0..1) that answer differently: 0 = the same view.
  static float dissimilarity(const FrameCode& a, const FrameCode& b);

 private:
  struct Test {
    int16_t pixel;     // in the thumbnail
    uint8_t channel;   // 0 depth, 1 grey
    float threshold;   // metres or grey level 0..1
  };
  std::vector<Test> tests_;  // kFerns * kTestsPerFern
};

}  // namespace vf::slam
