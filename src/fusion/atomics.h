#pragma once
// Atomics written once for host (GCC builtins) and device (CUDA intrinsics).
#include <cstdint>

#include "core/hd.h"

namespace vf {

VF_HD int atomicIncrement(int* counter) {
#if defined(__CUDA_ARCH__)
  return atomicAdd(counter, 1);
#else
  return __atomic_fetch_add(counter, 1, __ATOMIC_RELAXED);
#endif
}

// Many threads may store the same value to the same word (brick marking); make that well defined.
VF_HD void storeRelaxed(uint32_t* word, uint32_t value) {
#if defined(__CUDA_ARCH__)
  *reinterpret_cast<volatile uint32_t*>(word) = value;
#else
  __atomic_store_n(word, value, __ATOMIC_RELAXED);
#endif
}

VF_HD uint32_t loadRelaxed(const uint32_t* word) {
#if defined(__CUDA_ARCH__)
  return *reinterpret_cast<const volatile uint32_t*>(word);
#else
  return __atomic_load_n(word, __ATOMIC_RELAXED);
#endif
}

}  // namespace vf
