#include "slam/frame_code.h"

#include <cmath>

namespace vf::slam {
namespace {

// splitmix64: a portable generator, so that the tests (and the codes) are the same everywhere.
uint64_t nextRandom(uint64_t& state) {
  uint64_t z = (state += 0x9E3779B97F4A7C15ull);
  z = (z ^ (z >> 30)) * 0xBF58476D1CE4E5B9ull;
  z = (z ^ (z >> 27)) * 0x94D049BB133111EBull;
  return z ^ (z >> 31);
}

float uniform(uint64_t& state, float lo, float hi) {
  return lo + (hi - lo) * float(double(nextRandom(state) >> 11) * (1.0 / 9007199254740992.0));
}

constexpr float kMissing = -1.f;

// Mean of the valid values of each thumbnail cell; kMissing where a cell has none.
template <class Sample>
std::vector<float> thumbnail(int width, int height, Sample sample) {
  constexpr int tw = FernEncoder::kThumbWidth, th = FernEncoder::kThumbHeight;
  std::vector<float> out(size_t(tw) * th, kMissing);
  for (int ty = 0; ty < th; ++ty) {
    const int y0 = ty * height / th, y1 = (ty + 1) * height / th;
    for (int tx = 0; tx < tw; ++tx) {
      const int x0 = tx * width / tw, x1 = (tx + 1) * width / tw;
      double sum = 0;
      int count = 0;
      for (int y = y0; y < y1; y += 2)
        for (int x = x0; x < x1; x += 2) {
          const float v = sample(x, y);
          if (v >= 0.f) sum += v, ++count;
        }
      if (count > 0) out[size_t(ty) * tw + tx] = float(sum / count);
    }
  }
  return out;
}

}  // namespace

FernEncoder::FernEncoder() {
  uint64_t state = 0x5EEDC0DEull;
  tests_.resize(size_t(kFerns) * kTestsPerFern);
  for (Test& t : tests_) {
    t.pixel = int16_t(nextRandom(state) % uint64_t(kThumbWidth * kThumbHeight));
    t.channel = uint8_t(nextRandom(state) % 2);
    t.threshold = t.channel == 0 ? uniform(state, 0.5f, 4.0f) : uniform(state, 0.1f, 0.9f);
  }
}

FrameCode FernEncoder::encode(const RgbdFrame& frame, float min_depth_m, float max_depth_m) const {
  const DepthImage& depth = frame.depth;
  const std::vector<float> d = thumbnail(depth.width(), depth.height(), [&](int x, int y) {
    const float z = depth(x, y);
    return z >= min_depth_m && z <= max_depth_m ? z : kMissing;
  });
  int valid = 0;
  for (float z : d) valid += z > 0.f ? 1 : 0;
  FrameCode code;
  if (valid < int(d.size()) / 10) return code;  // a covered lens, a blank frame: no place to recognise
  std::vector<float> grey(d.size(), kMissing);
  if (!frame.color.empty()) {
    const ColorImage& c = frame.color;
    grey = thumbnail(c.width(), c.height(), [&](int x, int y) {
      const Rgb8 p = c(x, y);
      return (0.299f * p.r + 0.587f * p.g + 0.114f * p.b) / 255.f;
    });
    // Zero-mean over the frame (plus 0.5), so that an exposure change moves no test.
    double mean = 0;
    int n = 0;
    for (float g : grey)
      if (g >= 0.f) mean += g, ++n;
    if (n > 0)
      for (float& g : grey)
        if (g >= 0.f) g = std::fmin(std::fmax(g - float(mean / n) + 0.5f, 0.f), 1.f);
  }
  code.ferns.resize(kFerns);
  for (int f = 0; f < kFerns; ++f) {
    uint8_t bits = 0;
    for (int k = 0; k < kTestsPerFern; ++k) {
      const Test& t = tests_[size_t(f) * kTestsPerFern + size_t(k)];
      const float v = (t.channel == 0 ? d : grey)[size_t(t.pixel)];
      // A missing value answers as "far" / "bright": the same in both frames where both miss it.
      bits = uint8_t(bits | ((v >= 0.f && v < t.threshold) ? 1u << k : 0u));
    }
    code.ferns[size_t(f)] = bits;
  }
  return code;
}

float FernEncoder::dissimilarity(const FrameCode& a, const FrameCode& b) {
  if (a.ferns.size() != b.ferns.size() || a.ferns.empty()) return 1.f;
  int differ = 0;
  for (size_t i = 0; i < a.ferns.size(); ++i) differ += a.ferns[i] != b.ferns[i] ? 1 : 0;
  return float(differ) / float(a.ferns.size());
}

}  // namespace vf::slam
