// The GPU builds of the fusion functors: the same structs the CPU backend runs (src/fusion),
// instantiated here once each. A functor passed to vf::parallelFor / parallelReduce in
// src/fusion but missing from this list is an undefined symbol when vdbfuse links.
#include "fusion/brick_hash.h"
#include "fusion/icp_kernels.h"
#include "fusion/integrate_kernels.h"
#include "fusion/measurement_kernels.h"
#include "fusion/photometric_kernels.h"
#include "fusion/raycast_kernels.h"
#include "fusion/semantic_kernels.h"
#include "parallel.cuh"

// DESIGN.md: OpenVDB never appears in a .cu file; nor do TBB or Eigen (the CPU backend's tools).
#if defined(OPENVDB_LIBRARY_MAJOR_VERSION_NUMBER) || defined(TBB_VERSION_MAJOR) || \
    defined(EIGEN_WORLD_VERSION)
#error "a fusion kernel header pulled OpenVDB, TBB or Eigen into the CUDA backend"
#endif

namespace vf::cuda {

#define VF_CUDA_FOR(F) template void parallelFor<F>(int, const F&);

// measure (measurement_kernels.h, semantic_kernels.h)
VF_CUDA_FOR(DynamicMaskKernel)
VF_CUDA_FOR(ApplyMaskKernel)
VF_CUDA_FOR(BilateralFilterKernel)
VF_CUDA_FOR(DownsampleDepthKernel)
VF_CUDA_FOR(VertexMapKernel)
VF_CUDA_FOR(NormalMapKernel)
VF_CUDA_FOR(IntensityKernel)
VF_CUDA_FOR(DownsampleIntensityKernel)
VF_CUDA_FOR(DownsampleColorKernel)
VF_CUDA_FOR(IntensityGradientKernel)
// track (icp_kernels.h, photometric_kernels.h)
template void parallelReduce<normal_row::kSize, IcpKernel>(int, const IcpKernel&, double*);
template void parallelReduce<normal_row::kSize, PhotometricKernel>(int, const PhotometricKernel&, double*);
template void parallelReduce<2, ModelNormalScatterKernel>(int, const ModelNormalScatterKernel&, double*);
template void parallelReduceTwo<normal_row::kSize, IcpKernel, PhotometricKernel>(int, const IcpKernel&, int,
                                                                                 const PhotometricKernel&, double*,
                                                                                 double*);
// (cuda_parity_test compares the two-in-one launch with two separate ones on ICP rows.)
template void parallelReduceTwo<normal_row::kSize, IcpKernel, IcpKernel>(int, const IcpKernel&, int, const IcpKernel&,
                                                                         double*, double*);
// integrate (integrate_kernels.h) and the brick hash (brick_hash.h)
VF_CUDA_FOR(MarkBricksKernel)
VF_CUDA_FOR(CountNewBricksKernel)
VF_CUDA_FOR(AssignSlotsKernel)
VF_CUDA_FOR(IntegrateKernel)
VF_CUDA_FOR(ClearBrickHashKernel)
VF_CUDA_FOR(RehashBricksKernel)
VF_CUDA_FOR(SaveSlotStampsKernel)
// raycast (raycast_kernels.h)
VF_CUDA_FOR(ClearRangeKernel)
VF_CUDA_FOR(BrickRangeKernel)
VF_CUDA_FOR(RaycastKernel)
VF_CUDA_FOR(DownsamplePredictionKernel)
VF_CUDA_FOR(DownsampleModelIntensityKernel)

#undef VF_CUDA_FOR

}  // namespace vf::cuda
