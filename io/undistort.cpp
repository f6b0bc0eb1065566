#include "io/undistort.h"

#include <cmath>
#include <cstdint>
#include <cstring>
#include <string>

#if defined(__AVX2__)
#include <immintrin.h>
#endif

// The remaps below reproduce cv::remap (OpenCV 4, imgwarp.cpp) for float maps bit for bit, so
// that undistorted frames are the same with and without OpenCV (tests/io/undistort_test.cpp
// compares them): nearest neighbour rounds the map to the nearest integer (ties to even),
// bilinear works in 1/32 pixel steps with 15-bit fixed-point weights.

namespace vf {
namespace {

// OpenCV's cvRound / saturate_cast<short>: round to nearest, ties to even (the default FP mode).
inline int roundToInt(float v) { return int(std::lrint(v)); }
inline int saturateShort(int v) { return v < -32768 ? -32768 : v > 32767 ? 32767 : v; }
inline int clampIndex(int v, int size) { return v < 0 ? 0 : v >= size ? size - 1 : v; }

constexpr int kInterBits = 5;
constexpr int kInterTab = 1 << kInterBits;  // 32 sub-pixel steps
constexpr int kCoefBits = 15;

// Bilinear weights for a sub-pixel offset (fx, fy) in 1/32 steps, summing to 2^15 as OpenCV's
// BilinearTab_i: (32 - f) * (32 - g) * 32 and so on, except at (0, 0), where 2^15 does not fit a
// short and OpenCV's table holds {32767, 0, 0, 1}.
struct BilinearWeights {
  int w[kInterTab * kInterTab][4];
  // The same weights as 16-bit pairs: {w0 | w1 << 16, w2 | w3 << 16} (all fit: at most 32767).
  int32_t packed[kInterTab * kInterTab][2];
  BilinearWeights() {
    for (int fy = 0; fy < kInterTab; ++fy)
      for (int fx = 0; fx < kInterTab; ++fx) {
        int* t = w[fy * kInterTab + fx];
        t[0] = (kInterTab - fy) * (kInterTab - fx) * 32;
        t[1] = (kInterTab - fy) * fx * 32;
        t[2] = fy * (kInterTab - fx) * 32;
        t[3] = fy * fx * 32;
      }
    int* zero = w[0];
    zero[0] = 32767, zero[1] = 0, zero[2] = 0, zero[3] = 1;
    for (int i = 0; i < kInterTab * kInterTab; ++i) {
      packed[i][0] = int32_t(uint32_t(w[i][0]) | uint32_t(w[i][1]) << 16);
      packed[i][1] = int32_t(uint32_t(w[i][2]) | uint32_t(w[i][3]) << 16);
    }
  }
};

const BilinearWeights& bilinearWeights() {
  static const BilinearWeights weights;
  return weights;
}

// The input pixel nearest to the sample (x, y); outside the image: -1, or with `replicate` the
// nearest edge pixel.
int32_t nearestSource(float x, float y, int width, int height, bool replicate) {
  const int sx = saturateShort(roundToInt(x)), sy = saturateShort(roundToInt(y));
  if (unsigned(sx) < unsigned(width) && unsigned(sy) < unsigned(height)) return sy * width + sx;
  return replicate ? clampIndex(sy, height) * width + clampIndex(sx, width) : -1;
}

template <class T>
void remapNearest(const T* src, T* dst, const std::vector<int32_t>& source, T outside) {
  for (size_t i = 0; i < source.size(); ++i) dst[i] = source[i] >= 0 ? src[source[i]] : outside;
}

}  // namespace

Undistorter::BilinearTap Undistorter::bilinearTap(float x, float y) const {
  const int X = roundToInt(x * float(kInterTab)), Y = roundToInt(y * float(kInterTab));
  const int sx = saturateShort(X >> kInterBits), sy = saturateShort(Y >> kInterBits);
  BilinearTap tap;
  tap.weights = uint16_t((Y & (kInterTab - 1)) * kInterTab + (X & (kInterTab - 1)));
  if (sx >= width_ || sx + 1 < 0 || sy >= height_ || sy + 1 < 0) return tap;  // inside = 0
  tap.first = sy * width_ + sx;
  const bool x0 = sx >= 0, x1 = sx + 1 < width_, y0 = sy >= 0, y1 = sy + 1 < height_;
  tap.inside = uint8_t((x0 && y0) | (x1 && y0) << 1 | (x0 && y1) << 2 | (x1 && y1) << 3);
  return tap;
}

namespace {

// Two channels of an RGBA pixel in the two 32-bit halves of a word: r (or b) low, g (or a) high.
// Four taps weighted to 2^kCoefBits in all stay below 2^23 in each half, so one multiply weighs
// both channels and no carry crosses between them.
inline uint64_t lowChannels(uint32_t p) { return (p & 0xFFu) | uint64_t(p & 0xFF00u) << 24; }
inline uint64_t highChannels(uint32_t p) { return ((p >> 16) & 0xFFu) | uint64_t(p >> 24) << 32; }
inline uint8_t roundedChannel(uint64_t sum) {
  return uint8_t((uint32_t(sum) + (1u << (kCoefBits - 1))) >> kCoefBits);  // <= 255: the weights sum to 2^15
}

// The bilinear blend of the 2x2 pixels from p00 (row stride `width`) with weights w, as the
// per-channel sums of remapBilinearRgba's border path, two channels per multiply.
inline Rgb8 blendInterior(const Rgb8* p00, int width, const int* w) {
  uint32_t p[4];
  std::memcpy(&p[0], p00, 4);
  std::memcpy(&p[1], p00 + 1, 4);
  std::memcpy(&p[2], p00 + width, 4);
  std::memcpy(&p[3], p00 + width + 1, 4);
  uint64_t rg = 0, ba = 0;
  for (int k = 0; k < 4; ++k) {
    rg += lowChannels(p[k]) * uint64_t(w[k]);
    ba += highChannels(p[k]) * uint64_t(w[k]);
  }
  return {roundedChannel(rg), roundedChannel(rg >> 32), roundedChannel(ba), roundedChannel(ba >> 32)};
}

#if defined(__AVX2__)
// Two interior samples at once, the same sums as blendInterior: a sample's left and right taps
// are adjacent pixels (one 8-byte load per row), and every weight of the table fits a signed
// 16-bit lane (at most 32767), so one madd weighs a channel of both taps of a row, exact in 32
// bits. first: each sample's top-left input pixel; packed: its BilinearWeights::packed entry.
inline void blendInterior2(const Rgb8* src, int width, const int32_t first[2], const int32_t* const packed[2],
                           Rgb8* dst) {
  // Left and right taps' bytes interleaved channel by channel: r0 r1 g0 g1 b0 b1 a0 a1.
  const __m128i pair_channels = _mm_setr_epi8(0, 4, 1, 5, 2, 6, 3, 7, 8, 12, 9, 13, 10, 14, 11, 15);
  auto row = [&](int offset) {
    int64_t a, b;
    std::memcpy(&a, src + first[0] + offset, 8);
    std::memcpy(&b, src + first[1] + offset, 8);
    return _mm256_cvtepu8_epi16(_mm_shuffle_epi8(_mm_set_epi64x(b, a), pair_channels));  // sample 0 | sample 1
  };
  const __m256i top_weights = _mm256_setr_epi32(packed[0][0], packed[0][0], packed[0][0], packed[0][0], packed[1][0],
                                                packed[1][0], packed[1][0], packed[1][0]);
  const __m256i bottom_weights = _mm256_setr_epi32(packed[0][1], packed[0][1], packed[0][1], packed[0][1], packed[1][1],
                                                   packed[1][1], packed[1][1], packed[1][1]);
  const __m256i sum = _mm256_add_epi32(_mm256_madd_epi16(row(0), top_weights), _mm256_madd_epi16(row(width), bottom_weights));
  const __m256i rounded = _mm256_srli_epi32(_mm256_add_epi32(sum, _mm256_set1_epi32(1 << (kCoefBits - 1))), kCoefBits);
  const __m128i words = _mm_packs_epi32(_mm256_castsi256_si128(rounded), _mm256_extracti128_si256(rounded, 1));
  _mm_storel_epi64(reinterpret_cast<__m128i*>(dst), _mm_packus_epi16(words, words));
}
#endif

}  // namespace

// Bilinear, RGBA 8 bit, constant border `outside` for samples beyond the image.
void Undistorter::remapBilinearRgba(const Rgb8* src, Rgb8* dst, Rgb8 outside) const {
  const BilinearWeights& table = bilinearWeights();
  auto channels = [](const Rgb8& p, int k) { return k == 0 ? p.r : k == 1 ? p.g : k == 2 ? p.b : p.a; };
  auto sample = [&](size_t i) {
    const BilinearTap tap = bilinear_[i];
    if (tap.inside == 0) {
      dst[i] = outside;
      return;
    }
    const int* w = table.w[tap.weights];
    // first is -1 or less at the top and left borders: each tap is read only where it is inside.
    const int32_t f = tap.first;
    if (tap.inside == 15) {  // the common case: no tap at the border
      dst[i] = blendInterior(src + f, width_, w);
      return;
    }
    const Rgb8& p00 = (tap.inside & 1) ? src[f] : outside;
    const Rgb8& p01 = (tap.inside & 2) ? src[f + 1] : outside;
    const Rgb8& p10 = (tap.inside & 4) ? src[f + width_] : outside;
    const Rgb8& p11 = (tap.inside & 8) ? src[f + width_ + 1] : outside;
    uint8_t out[4];
    for (int k = 0; k < 4; ++k) {
      const int sum = channels(p00, k) * w[0] + channels(p01, k) * w[1] + channels(p10, k) * w[2] +
                      channels(p11, k) * w[3];
      const int v = (sum + (1 << (kCoefBits - 1))) >> kCoefBits;
      out[k] = uint8_t(v < 0 ? 0 : v > 255 ? 255 : v);
    }
    dst[i] = {out[0], out[1], out[2], out[3]};
  };
  size_t i = 0;
#if defined(__AVX2__)
  // Interior samples (nearly all of a frame) two at a time in vector lanes.
  for (; i + 2 <= bilinear_.size(); i += 2) {
    const BilinearTap t0 = bilinear_[i], t1 = bilinear_[i + 1];
    if ((t0.inside & t1.inside) == 15) {
      const int32_t first[2] = {t0.first, t1.first};
      const int32_t* const packed[2] = {table.packed[t0.weights], table.packed[t1.weights]};
      blendInterior2(src, width_, first, packed, dst + i);
    } else {
      sample(i);
      sample(i + 1);
    }
  }
#endif
  for (; i < bilinear_.size(); ++i) sample(i);
}

Undistorter::Undistorter(const Intrinsics& K, const Distortion& d) : width_(K.width), height_(K.height) {
  if (!K.valid()) throw Error("undistortion needs valid intrinsics with an image size");
  map_x_.resize(size_t(width_) * height_);
  map_y_.resize(size_t(width_) * height_);
  // Same model and result as cv::initUndistortRectifyMap(K, d, I, K): for each undistorted pixel,
  // project its ray through the Brown-Conrady model to find where the lens put it.
  for (int v = 0; v < height_; ++v)
    for (int u = 0; u < width_; ++u) {
      const double x = (u - double(K.cx)) / K.fx, y = (v - double(K.cy)) / K.fy;
      const double r2 = x * x + y * y;
      const double radial = 1 + r2 * (d.k1 + r2 * (d.k2 + r2 * d.k3));
      const double xd = x * radial + 2 * d.p1 * x * y + d.p2 * (r2 + 2 * x * x);
      const double yd = y * radial + d.p1 * (r2 + 2 * y * y) + 2 * d.p2 * x * y;
      map_x_[size_t(v) * width_ + u] = float(K.fx * xd + K.cx);
      map_y_[size_t(v) * width_ + u] = float(K.fy * yd + K.cy);
    }
  const size_t pixels = map_x_.size();
  nearest_.resize(pixels);
  nearest_clamped_.resize(pixels);
  bilinear_.resize(pixels);
  for (size_t i = 0; i < pixels; ++i) {
    nearest_[i] = nearestSource(map_x_[i], map_y_[i], width_, height_, false);
    nearest_clamped_[i] = nearestSource(map_x_[i], map_y_[i], width_, height_, true);
    bilinear_[i] = bilinearTap(map_x_[i], map_y_[i]);
  }
}

void Undistorter::checkSize(int width, int height, const char* what) const {
  if (width != width_ || height != height_)
    throw Error(std::string("cannot undistort ") + what + " of " + std::to_string(width) + "x" +
                std::to_string(height) + ": the calibration is for " + std::to_string(width_) + "x" +
                std::to_string(height_));
}

DepthImage Undistorter::undistortDepth(const DepthImage& depth_m) const {
  checkSize(depth_m.width(), depth_m.height(), "depth");
  DepthImage out = DepthImage::forOverwrite(width_, height_);  // every pixel remapped
  remapNearest(depth_m.data(), out.data(), nearest_, 0.f);
  return out;
}

ColorImage Undistorter::undistortColor(const ColorImage& color) const {
  checkSize(color.width(), color.height(), "colour");
  ColorImage out = ColorImage::forOverwrite(width_, height_);  // every pixel remapped
  remapBilinearRgba(color.data(), out.data(), Rgb8{0, 0, 0, 255});
  return out;
}

LabelImage Undistorter::undistortLabels(const LabelImage& labels) const {
  checkSize(labels.width(), labels.height(), "label map");
  LabelImage out = LabelImage::forOverwrite(width_, height_);  // every pixel remapped
  remapNearest(labels.data(), out.data(), nearest_clamped_, uint16_t(0));
  return out;
}

}  // namespace vf
