#pragma once
// Atomics written once for host (GCC builtins) and device (CUDA intrinsics).
#include <cstdint>
#include <cstring>

#include "core/hd.h"

namespace vf {

VF_HD int __float_as_int_vf(float f) {
  int i;
  memcpy(&i, &f, sizeof(i));
  return i;
}

VF_HD int atomicIncrement(int* counter) {
#if defined(__CUDA_ARCH__)
  return atomicAdd(counter, 1);
#else
  return __atomic_fetch_add(counter, 1, __ATOMIC_RELAXED);
#endif
}

// Returns the previous value; many threads may race on the same word (brick marking).
VF_HD uint32_t exchange(uint32_t* word, uint32_t value) {
#if defined(__CUDA_ARCH__)
  return atomicExch(word, value);
#else
  return __atomic_exchange_n(word, value, __ATOMIC_RELAXED);
#endif
}

// Min / max of non-negative floats through their bit patterns, which order like the integers.
VF_HD void atomicMinNonNegative(float* target, float value) {
  int* word = reinterpret_cast<int*>(target);
  const int bits = __float_as_int_vf(value);
#if defined(__CUDA_ARCH__)
  atomicMin(word, bits);
#else
  int seen = __atomic_load_n(word, __ATOMIC_RELAXED);
  while (bits < seen && !__atomic_compare_exchange_n(word, &seen, bits, true, __ATOMIC_RELAXED, __ATOMIC_RELAXED)) {
  }
#endif
}

VF_HD void atomicMaxNonNegative(float* target, float value) {
  int* word = reinterpret_cast<int*>(target);
  const int bits = __float_as_int_vf(value);
#if defined(__CUDA_ARCH__)
  atomicMax(word, bits);
#else
  int seen = __atomic_load_n(word, __ATOMIC_RELAXED);
  while (bits > seen && !__atomic_compare_exchange_n(word, &seen, bits, true, __ATOMIC_RELAXED, __ATOMIC_RELAXED)) {
  }
#endif
}

VF_HD uint32_t loadRelaxed(const uint32_t* word) {
#if defined(__CUDA_ARCH__)
  return *reinterpret_cast<const volatile uint32_t*>(word);
#else
  return __atomic_load_n(word, __ATOMIC_RELAXED);
#endif
}

VF_HD uint64_t loadRelaxed(const uint64_t* word) {
#if defined(__CUDA_ARCH__)
  return *reinterpret_cast<const volatile unsigned long long*>(word);
#else
  return __atomic_load_n(word, __ATOMIC_RELAXED);
#endif
}

// Stores `desired` where *word == expected; returns the value found (== expected on success).
VF_HD uint64_t compareExchange(uint64_t* word, uint64_t expected, uint64_t desired) {
#if defined(__CUDA_ARCH__)
  return atomicCAS(reinterpret_cast<unsigned long long*>(word), (unsigned long long)expected,
                   (unsigned long long)desired);
#else
  __atomic_compare_exchange_n(word, &expected, desired, false, __ATOMIC_RELAXED, __ATOMIC_RELAXED);
  return expected;
#endif
}

}  // namespace vf
