#pragma once
// VF_HD marks functions that run on the host and, when compiled by nvcc, on the device.
// Every per-pixel / per-voxel rule is written once with it (DESIGN.md, "one kernel, two backends").
#if defined(__CUDACC__)
#define VF_HD __host__ __device__ __forceinline__
#else
#define VF_HD inline
#endif

// VF_SIMD_LOOP before a loop over vector lanes asks the host compiler to vectorise that loop
// (`#pragma omp simd`, honoured where the target compiles with -fopenmp-simd, as vf_fusion
// does); nvcc gets nothing.
#if defined(__CUDACC__)
#define VF_SIMD_LOOP
#else
#define VF_SIMD_LOOP _Pragma("omp simd")
#endif
