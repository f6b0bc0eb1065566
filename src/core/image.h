#pragma once
#include <cstdint>
#include <memory>
#include <vector>

#include "core/error.h"
#include "core/math.h"

namespace vf {

// Non-owning view of a row-major image; what kernels receive (host or device pointer).
template <class T>
struct ImageView {
  T* data = nullptr;
  int width = 0, height = 0;

  VF_HD T& operator()(int x, int y) const { return data[y * width + x]; }
  VF_HD T& operator[](int i) const { return data[i]; }
  VF_HD int size() const { return width * height; }
  VF_HD bool inside(int x, int y) const { return x >= 0 && y >= 0 && x < width && y < height; }
};

// An allocator whose value-initialisation is default-initialisation: a vector of plain pixels
// grows without being zeroed first.
template <class T>
struct DefaultInitAllocator : std::allocator<T> {
  template <class U>
  struct rebind {
    using other = DefaultInitAllocator<U>;
  };
  DefaultInitAllocator() = default;
  template <class U>
  DefaultInitAllocator(const DefaultInitAllocator<U>&) noexcept {}
  template <class U>
  void construct(U* p) noexcept {
    ::new (static_cast<void*>(p)) U;
  }
  template <class U, class... Args>
  void construct(U* p, Args&&... args) {
    ::new (static_cast<void*>(p)) U(std::forward<Args>(args)...);
  }
};

// Host-owned image.
template <class T>
class Image {
 public:
  Image() = default;
  Image(int width, int height, T fill = T{}) { resize(width, height, fill); }
  void resize(int width, int height, T fill = T{}) {
    setSize(width, height);
    pixels_.assign(size_t(width) * size_t(height), fill);
  }
  // An image whose every pixel the caller writes next (a decoder, a remap): its pixels are not
  // filled first, which cost a frame's decoding a pass over each image for nothing.
  static Image forOverwrite(int width, int height) {
    Image image;
    image.setSize(width, height);
    image.pixels_.resize(size_t(width) * size_t(height));
    return image;
  }
  int width() const { return width_; }
  int height() const { return height_; }
  bool empty() const { return pixels_.empty(); }
  T* data() { return pixels_.data(); }
  const T* data() const { return pixels_.data(); }
  T& operator()(int x, int y) { return pixels_[size_t(y) * width_ + x]; }
  const T& operator()(int x, int y) const { return pixels_[size_t(y) * width_ + x]; }
  ImageView<T> view() { return {pixels_.data(), width_, height_}; }
  ImageView<const T> view() const { return {pixels_.data(), width_, height_}; }

 private:
  void setSize(int width, int height) {
    if (width < 0 || height < 0) throw Error("image size must not be negative");
    width_ = width;
    height_ = height;
  }
  int width_ = 0, height_ = 0;
  std::vector<T, DefaultInitAllocator<T>> pixels_;
};

// Work items of an image sampled at every stride-th pixel in x and y (item = row * columns +
// column), and the pixel of each.
VF_HD int stridedColumns(int width, int stride) { return (width + stride - 1) / stride; }
VF_HD int stridedPixelCount(int width, int height, int stride) {
  return stridedColumns(width, stride) * stridedColumns(height, stride);
}
VF_HD int stridedPixel(int item, int width, int stride) {
  const int cols = stridedColumns(width, stride);
  return (item / cols) * stride * width + (item % cols) * stride;
}

using DepthImage = Image<float>;   // metres, 0 = no reading
using ColorImage = Image<Rgb8>;    // sRGB 8 bit
using LabelImage = Image<uint16_t>;  // class id per pixel

}  // namespace vf
