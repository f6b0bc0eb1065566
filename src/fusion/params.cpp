#include "fusion/params.h"

#include <cmath>
#include <sstream>

#include "core/error.h"

namespace vf {
namespace {

template <class T>
void require(bool ok, const char* field, T value, const char* expectation) {
  if (ok) return;
  std::ostringstream msg;
  msg << field << " = " << value << ": " << expectation;
  throw Error(msg.str());
}

}  // namespace

void MeasurementParams::validate() const {
  require(min_depth_m >= 0, "MeasurementParams.min_depth_m", min_depth_m, "must be >= 0");
  require(max_depth_m > min_depth_m && max_depth_m <= 100.f, "MeasurementParams.max_depth_m", max_depth_m,
          "must exceed min_depth_m and be at most 100 m");
  require(bilateral_radius_px >= 0 && bilateral_radius_px <= 3, "MeasurementParams.bilateral_radius_px",
          bilateral_radius_px, "must be in [0, 3]");
  require(bilateral_sigma_px > 0, "MeasurementParams.bilateral_sigma_px", bilateral_sigma_px, "must be > 0");
  require(bilateral_sigma_m > 0, "MeasurementParams.bilateral_sigma_m", bilateral_sigma_m, "must be > 0");
  require(pyramid_depth_jump_m > 0, "MeasurementParams.pyramid_depth_jump_m", pyramid_depth_jump_m, "must be > 0");
  require(normal_max_jump_m > 0, "MeasurementParams.normal_max_jump_m", normal_max_jump_m, "must be > 0");
}

void IcpParams::validate() const {
  for (int it : iterations) require(it >= 0 && it <= 100, "IcpParams.iterations", it, "must be in [0, 100]");
  require(iterations[0] + iterations[1] + iterations[2] > 0, "IcpParams.iterations", 0, "need at least one");
  for (int stride : stride_px) require(stride >= 1 && stride <= 8, "IcpParams.stride_px", stride, "must be in [1, 8]");
  require(max_distance_m > 0, "IcpParams.max_distance_m", max_distance_m, "must be > 0");
  for (float px : convergence_px)
    require(px >= 0 && px <= 1, "IcpParams.convergence_px", px, "must be in [0, 1]");
  require(max_normal_angle_deg > 0 && max_normal_angle_deg <= 90, "IcpParams.max_normal_angle_deg",
          max_normal_angle_deg, "must be in (0, 90]");
  require(huber_m > 0, "IcpParams.huber_m", huber_m, "must be > 0");
  require(model_window_frames >= 0, "IcpParams.model_window_frames", model_window_frames, "must be >= 0 (0: the whole model)");
  require(photometric_weight >= 0, "IcpParams.photometric_weight", photometric_weight, "must be >= 0");
  require(photometric_huber > 0, "IcpParams.photometric_huber", photometric_huber, "must be > 0");
  require(min_inlier_fraction >= 0 && min_inlier_fraction < 1, "IcpParams.min_inlier_fraction",
          min_inlier_fraction, "must be in [0, 1)");
  require(max_rmse_m > 0, "IcpParams.max_rmse_m", max_rmse_m, "must be > 0");
  require(max_translation_m > 0, "IcpParams.max_translation_m", max_translation_m, "must be > 0");
  require(max_rotation_deg > 0, "IcpParams.max_rotation_deg", max_rotation_deg, "must be > 0");
  require(max_jump_m > 0, "IcpParams.max_jump_m", max_jump_m, "must be > 0");
  require(max_jump_deg > 0, "IcpParams.max_jump_deg", max_jump_deg, "must be > 0");
  require(min_covered_match >= 0 && min_covered_match < 1, "IcpParams.min_covered_match", min_covered_match,
          "must be in [0, 1)");
  require(relocalise_min_inlier_fraction >= 0 && relocalise_min_inlier_fraction < 1,
          "IcpParams.relocalise_min_inlier_fraction", relocalise_min_inlier_fraction, "must be in [0, 1)");
  require(relocalise_max_rmse_m > 0, "IcpParams.relocalise_max_rmse_m", relocalise_max_rmse_m, "must be > 0");
  require(relocalise_min_covered_match > 0 && relocalise_min_covered_match <= 1,
          "IcpParams.relocalise_min_covered_match", relocalise_min_covered_match, "must be in (0, 1]");
  require(relocalise_min_coverage > 0 && relocalise_min_coverage <= 1, "IcpParams.relocalise_min_coverage",
          relocalise_min_coverage, "must be in (0, 1]");
  require(depth_noise_quadratic >= 0 && std::isfinite(depth_noise_quadratic), "IcpParams.depth_noise_quadratic",
          depth_noise_quadratic, "must be >= 0");
  require(depth_noise_power == 1 || depth_noise_power == 2, "IcpParams.depth_noise_power", depth_noise_power,
          "must be 1 or 2");
  require(degenerate_share >= 0 && degenerate_share < 1, "IcpParams.degenerate_share", degenerate_share,
          "must be in [0, 1)");
}

void IntegrationParams::validate() const {
  require(max_weight >= 1 && max_weight <= 65535, "IntegrationParams.max_weight", max_weight, "must be in [1, 65535]");
}

void RaycastParams::validate() const {
  require(min_step_vox > 0.05f && min_step_vox <= 4, "RaycastParams.min_step_vox", min_step_vox,
          "must be in (0.05, 4]");
  require(step_fraction > 0 && step_fraction <= 1, "RaycastParams.step_fraction", step_fraction,
          "must be in (0, 1]");
  require(prediction_level >= 0 && prediction_level <= 2, "RaycastParams.prediction_level", prediction_level,
          "must be 0, 1 or 2");
}

void PipelineParams::validate() const {
  volume.validate();
  require(dynamic_mask_dilation_px >= 0 && dynamic_mask_dilation_px <= 64, "PipelineParams.dynamic_mask_dilation_px",
          dynamic_mask_dilation_px, "must be in [0, 64] pixels");
  measurement.validate();
  icp.validate();
  integration.validate();
  raycast.validate();
}

}  // namespace vf
