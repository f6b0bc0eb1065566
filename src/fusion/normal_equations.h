#pragma once
// The rows tracking reduces: one per pixel, the pixel's share of the 6x6 Gauss-Newton normal
// equations for a left-multiplied pose increment xi = (omega, v), plus the statistics that
// judge the result. IcpKernel and PhotometricKernel fill them (packNormalRows), parallelReduce
// sums them, and the host solves the sum (fusion/tracking.cpp). Slots are named, never counted.
#include "core/hd.h"

namespace vf {

namespace normal_row {
constexpr int kHessian = 0;         // 21 entries: the upper triangle of J^T W J, row by row
constexpr int kGradient = 21;       // 6 entries: J^T W r
constexpr int kSquaredError = 27;   // W r^2
constexpr int kInliers = 28;        // geometric correspondences found
constexpr int kMeasured = 29;       // measured pixels with a normal, matched or not
constexpr int kCovered = 30;        // measured pixels that land on the model's surface, matched or not
constexpr int kSize = 31;
}  // namespace normal_row

// Writes the weighted Jacobian products of L residuals into row[kHessian .. kSquaredError][lane]
// (kernels evaluate L pixels together): each product is one loop over the lanes, which the CPU
// compiler vectorises.
template <int L>
VF_HD void packNormalRows(float (&row)[normal_row::kSize][L], const float (&J)[6][L], const float (&residual)[L],
                          const float (&weight)[L]) {
  int k = normal_row::kHessian;
  for (int p = 0; p < 6; ++p)
    for (int q = p; q < 6; ++q, ++k)
      for (int j = 0; j < L; ++j) row[k][j] = weight[j] * J[p][j] * J[q][j];
  for (int p = 0; p < 6; ++p)
    for (int j = 0; j < L; ++j) row[normal_row::kGradient + p][j] = weight[j] * J[p][j] * residual[j];
  for (int j = 0; j < L; ++j) row[normal_row::kSquaredError][j] = weight[j] * residual[j] * residual[j];
}

// One element's row from a kernel's rows<L>() (CUDA's reduction takes one element per thread).
template <class Kernel>
VF_HD bool singleRow(const Kernel& kernel, int item, float* row) {
  float lane[normal_row::kSize][1];
  if (!kernel.template rows<1>(item, item + 1, lane)) return false;
  for (int k = 0; k < normal_row::kSize; ++k) row[k] = lane[k][0];
  return true;
}

}  // namespace vf
