#pragma once
// What an error in a FIXED parameter costs. A fixed parameter off by delta (a gauge's base
// point measured 1 mm wrong) is not seen as such: the calibration moves the free parameters
// to explain the readings as well as it can, and the pose error that remains is the bias the
// wrong value leaves in the calibrated machine. To first order, with J_f the identification
// Jacobian of the free parameters and j_k the column of fixed parameter k (whitened residuals
// as the calibration sees them):
//   free parameters after re-calibration   dx = pinv(J_f) j_k delta
//   residual the error leaves               r  = j_k delta - J_f dx   (often almost nothing)
//   pose error at configuration q           e  = P_k(q) delta - P_f(q) dx
// with P = J_pose_params (mechanism parameters; sensor parameters do not move the pose).
// `observability --sensitivity` prints it for every fixed parameter; the test checks it
// against a real, nonlinear re-calibration.

#include <memory>
#include <nlohmann/json.hpp>
#include <string>
#include <vector>

#include "kincal/framework/calibration/calibration_problem.hpp"

namespace kincal {

struct FixedParameterSensitivity {
  std::string name, unit;
  double delta = 0;  ///< the error assumed in the parameter (its unit)
  /// RMS over the readings of the residual the error leaves after re-calibration, in the
  /// readings' units (whitened residuals times each reading's std): how visible it is.
  double residual_rms = 0;
  /// Pose error over the workspace configurations after re-calibration: mean and max of
  /// |position error| (mm) and of |orientation error| (rad, rotation angle).
  double position_mean = 0, position_max = 0;
  double orientation_mean = 0, orientation_max = 0;
};

struct SensitivityResult {
  std::vector<FixedParameterSensitivity> rows;  ///< one per fixed parameter, model order
  int free_rank = 0;                            ///< numerical rank of J_f (column-scaled)
  int num_free = 0;
};

/// For every parameter not in `free`: the effect of an error of `delta_mm` (mm parameters)
/// or `delta_rad` (rad parameters), calibrating from `calibration` and measuring the pose
/// error at the configurations of `workspace` (may be the same data). Throws
/// std::runtime_error when the model cannot be evaluated at `values` on either set.
SensitivityResult fixed_parameter_sensitivity(std::shared_ptr<const MeasurementModel> model,
                                              const VectorXd& values,
                                              const Measurements& calibration,
                                              const Measurements& workspace,
                                              const std::vector<int>& free, double delta_mm,
                                              double delta_rad);

/// One object per fixed parameter: name, unit, error, residual_rms, position_mean_mm,
/// position_max_mm, orientation_mean_rad, orientation_max_rad.
nlohmann::ordered_json to_json(const SensitivityResult& s);

}  // namespace kincal
