#pragma once
// GPU tests skip, saying why, where no CUDA GPU can be used (CI has nvcc but no GPU).
#include <gtest/gtest.h>

#include "fusion/cuda_api.h"
#include "fusion/device.h"

#define VF_REQUIRE_GPU()                                                                        \
  do {                                                                                          \
    if (::vf::cudaDeviceCount() == 0)                                                           \
      GTEST_SKIP() << "no CUDA GPU: " << ::vf::cuda::lastErrorDescription();                    \
  } while (0)
