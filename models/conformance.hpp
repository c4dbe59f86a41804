#pragma once
// The conformance checks every model type is held to, built into the library so that
// `kincal check` (a plug-in author's tool) and the ctest suite (tests/models/
// model_conformance_test.cpp, every registered preset) run the same code:
//   - the model file round-trips exactly, and every unit is declared;
//   - every analytic Jacobian against central finite differences, at configurations drawn
//     as a simulation draws them: the mechanism's d pose / d params and d pose / d q, each
//     sensor's d reading / d pose and d reading / d params, the calibration residuals';
//   - inverse kinematics of forward kinematics returns to the same pose;
//   - zero-noise recovery: from the nominal geometry, every least-squares backend reaches
//     the true value of every free parameter within 1e-6 (of its unit).
// Each check is a verdict with the worst error it found and where; nothing throws out of
// them (an exception in a model's code is that check's failure).

#include <functional>
#include <memory>
#include <string>
#include <vector>

#include "kincal/framework/extension/model_registry.hpp"
#include "kincal/framework/kinematics/measurement_model.hpp"
#include "kincal/framework/least_squares/solver_registry.hpp"

namespace kincal {

struct ConformanceCheck {
  std::string name;  ///< e.g. "J_reading_pose of sensor 'laser'"
  bool passed = false;
  double worst = 0;      ///< the worst error found (relative for Jacobians); NaN if none
  double tolerance = 0;  ///< what `worst` is held to
  std::string detail;    ///< where the worst error is, or why the check could not run
};

/// A fresh model to check (a preset's factory, or a model file read again).
using ModelFactory = std::function<std::shared_ptr<MeasurementModel>()>;

/// One entry of the numerical-Jacobian comparison: the worst |analytic - numeric| /
/// (1 + |numeric|) and where. Passes when worst <= tolerance.
ConformanceCheck compare_jacobians(const std::string& name, const MatrixXd& analytic,
                                   const MatrixXd& numeric, double tolerance,
                                   const std::vector<std::string>& column_names = {});
/// f's Jacobian at x by central differences with step h.
MatrixXd numerical_jacobian(const std::function<VectorXd(const VectorXd&)>& f, const VectorXd& x,
                            double h);

/// The model file round trip and declared units.
std::vector<ConformanceCheck> check_model_file(const ModelFactory& make);
/// J_pose_params and J_pose_actuators of the mechanism (4 configurations each).
std::vector<ConformanceCheck> check_mechanism_jacobians(const ModelFactory& make);
/// J_reading_pose and J_reading_params of every sensor.
std::vector<ConformanceCheck> check_sensor_jacobians(const ModelFactory& make);
/// The calibration residuals' Jacobian (what every solver uses).
std::vector<ConformanceCheck> check_residual_jacobian(const ModelFactory& make);
/// Inverse kinematics of forward kinematics, over a simulation's configurations.
std::vector<ConformanceCheck> check_inverse_kinematics(const ModelFactory& make);
/// Zero-noise recovery by every least-squares backend of `solvers` (featured variants,
/// seeds 1 and 2): one check per backend.
std::vector<ConformanceCheck> check_recovery(const ModelFactory& make,
                                             const SolverRegistry& solvers);
/// All of the above, in that order.
std::vector<ConformanceCheck> check_model(const ModelFactory& make, const SolverRegistry& solvers);

/// Every mechanism and sensor type of `registry` appears in one of its presets (else no
/// check reaches it), and every preset frees a parameter and has a description.
std::vector<ConformanceCheck> check_registry_coverage(const ModelRegistry& registry);

}  // namespace kincal
