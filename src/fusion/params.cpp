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
  require(min_depth_m >= 0, "min_depth_m", min_depth_m, "must be >= 0");
  require(max_depth_m > min_depth_m, "max_depth_m", max_depth_m, "must exceed min_depth_m");
  require(bilateral_radius_px >= 0 && bilateral_radius_px <= 3, "bilateral_radius_px",
          bilateral_radius_px, "must be in [0, 3]");
  require(bilateral_sigma_px > 0, "bilateral_sigma_px", bilateral_sigma_px, "must be > 0");
  require(bilateral_sigma_m > 0, "bilateral_sigma_m", bilateral_sigma_m, "must be > 0");
  require(pyramid_depth_jump_m > 0, "pyramid_depth_jump_m", pyramid_depth_jump_m, "must be > 0");
}

void IcpParams::validate() const {
  for (int it : iterations) require(it >= 0 && it <= 100, "icp iterations", it, "must be in [0, 100]");
  require(iterations[0] + iterations[1] + iterations[2] > 0, "icp iterations", 0, "need at least one");
  require(finest_stride_px >= 1 && finest_stride_px <= 8, "icp finest_stride_px", finest_stride_px,
          "must be in [1, 8]");
  require(max_distance_m > 0, "icp max_distance_m", max_distance_m, "must be > 0");
  require(max_normal_angle_deg > 0 && max_normal_angle_deg <= 90, "icp max_normal_angle_deg",
          max_normal_angle_deg, "must be in (0, 90]");
  require(huber_m > 0, "icp huber_m", huber_m, "must be > 0");
  require(photometric_weight >= 0, "icp photometric_weight", photometric_weight, "must be >= 0");
  require(photometric_huber > 0, "icp photometric_huber", photometric_huber, "must be > 0");
  require(photometric_stride_px >= 1 && photometric_stride_px <= 8, "icp photometric_stride_px",
          photometric_stride_px, "must be in [1, 8]");
  require(min_inlier_fraction >= 0 && min_inlier_fraction < 1, "icp min_inlier_fraction",
          min_inlier_fraction, "must be in [0, 1)");
  require(max_rmse_m > 0, "icp max_rmse_m", max_rmse_m, "must be > 0");
  require(max_translation_m > 0, "icp max_translation_m", max_translation_m, "must be > 0");
  require(max_rotation_deg > 0, "icp max_rotation_deg", max_rotation_deg, "must be > 0");
}

void IntegrationParams::validate() const {
  require(max_weight >= 1 && max_weight <= 65535, "max_weight", max_weight, "must be in [1, 65535]");
}

void RaycastParams::validate() const {
  require(min_step_vox > 0.05f && min_step_vox <= 4, "raycast min_step_vox", min_step_vox,
          "must be in (0.05, 4]");
  require(step_fraction > 0 && step_fraction <= 1, "raycast step_fraction", step_fraction,
          "must be in (0, 1]");
  require(prediction_level >= 0 && prediction_level <= 2, "raycast prediction_level", prediction_level,
          "must be 0, 1 or 2");
}

void PipelineParams::validate() const {
  volume.validate();
  measurement.validate();
  icp.validate();
  integration.validate();
  raycast.validate();
}

}  // namespace vf
