#pragma once
// VF_HD marks functions that run on the host and, when compiled by nvcc, on the device.
// Every per-pixel / per-voxel rule is written once with it (DESIGN.md, "one kernel, two backends").
#if defined(__CUDACC__)
#define VF_HD __host__ __device__ __forceinline__
#else
#define VF_HD inline
#endif
