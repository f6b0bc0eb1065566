#pragma once
// A typed array that lives in host memory (CPU backend) or GPU memory (CUDA backend). The
// pipeline allocates all of them once, up front, so no stage allocates per frame.
#include <cstring>
#include <utility>
#include <vector>

#include "core/image.h"
#include "fusion/cuda_api.h"
#include "fusion/device.h"

namespace vf {

template <class T>
class Buffer {
 public:
  Buffer() = default;
  Buffer(Device device, size_t count) { allocate(device, count); }
  ~Buffer() { reset(); }
  Buffer(const Buffer&) = delete;
  Buffer& operator=(const Buffer&) = delete;
  Buffer(Buffer&& o) noexcept { *this = std::move(o); }
  Buffer& operator=(Buffer&& o) noexcept {
    if (this != &o) {
      reset();
      std::swap(data_, o.data_);
      std::swap(count_, o.count_);
      std::swap(device_, o.device_);
    }
    return *this;
  }

  void allocate(Device device, size_t count) {
    reset();
    device_ = device;
    count_ = count;
    if (count == 0) return;
    if (device == Device::Cuda) {
      data_ = static_cast<T*>(cuda::allocate(count * sizeof(T)));
      cuda::fillZero(data_, count * sizeof(T));
    } else {
      data_ = new T[count]();
    }
  }
  void reset() {
    if (data_) {
      if (device_ == Device::Cuda) cuda::release(data_);
      else delete[] data_;
    }
    data_ = nullptr;
    count_ = 0;
  }

  T* data() const { return data_; }
  size_t size() const { return count_; }
  Device device() const { return device_; }

  void upload(const T* host, size_t count) {
    if (count > count_) throw Error("buffer upload larger than its allocation");
    if (device_ == Device::Cuda) cuda::copyToDevice(data_, host, count * sizeof(T));
    else std::memcpy(data_, host, count * sizeof(T));
  }
  void download(T* host, size_t count) const {
    if (count > count_) throw Error("buffer download larger than its allocation");
    if (device_ == Device::Cuda) cuda::copyToHost(host, data_, count * sizeof(T));
    else std::memcpy(host, data_, count * sizeof(T));
  }
  void zero() {
    if (device_ == Device::Cuda) cuda::fillZero(data_, count_ * sizeof(T));
    else std::memset(static_cast<void*>(data_), 0, count_ * sizeof(T));
  }

 private:
  T* data_ = nullptr;
  size_t count_ = 0;
  Device device_ = Device::Cpu;
};

// An image-shaped buffer.
template <class T>
struct ImageBuffer {
  Buffer<T> buffer;
  int width = 0, height = 0;

  void allocate(Device device, int w, int h) {
    buffer.allocate(device, size_t(w) * size_t(h));
    width = w;
    height = h;
  }
  ImageView<T> view() const { return {buffer.data(), width, height}; }
  int size() const { return width * height; }
};

}  // namespace vf
