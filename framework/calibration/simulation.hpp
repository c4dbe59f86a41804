#pragma once
// Simulated calibration experiments, all drawn from one seed:
//   true parameters = nominal + U[-e, e] on every free parameter (e per parameter, or per
//                     unit: mm, rad, px, a plug-in's),
//   configurations  = home actuator values (nominal model) + U[-r, r] per actuator (r from
//                     the model's actuator ranges, or per unit),
//   readings        = sensors at the true pose + U[-a, a] noise per reading (a per unit),
//   validation set  = more configurations drawn the same way, with their true poses.
// Each part uses its own sub-stream of the seed, so changing the noise level does not
// change the configurations, and a seed reproduces a scenario bit for bit.

#include <cstdint>
#include <limits>
#include <memory>
#include <string>
#include <vector>

#include "kincal/framework/calibration/calibration_problem.hpp"
#include "kincal/framework/calibration/calibration_solve.hpp"
#include "kincal/framework/calibration/fit_check.hpp"
#include "kincal/framework/calibration/multi_start.hpp"
#include "kincal/framework/kinematics/units.hpp"
#include "kincal/framework/least_squares/solver.hpp"

namespace kincal {

struct ScenarioOptions {
  int num_configurations = 30;
  /// a per unit: a reading in that unit gets U[-a, a] noise (applied in the tangent space of
  /// manifold readings, Sensor::retract); a unit not given: none.
  UnitValues noise_half_width;
  /// e per unit: a free parameter in that unit gets U[-e, e] errors, unless it has its own
  /// (Parameter::error_half_width, from the model file); a unit not given: none.
  UnitValues param_error_half_width{5, 0.01};
  /// r per unit: every actuator in that unit is drawn within +-r of home instead of its range
  /// in the model (MeasurementModel::actuator_ranges()); a unit not given: the model's.
  UnitValues config_range;
  int num_validation = 200;
  std::uint64_t seed = 1;
  /// Per unit, when > 0: a Gaussian prior of this std around nominal on every free parameter
  /// in that unit, replacing the model's own prior_std, and the calibration is a MAP estimate
  /// (PriorProblem). A prior needs whitened residuals: a model that states no reading_std
  /// gets the noise's, a / sqrt(3) per unit, which must then be > 0.
  UnitValues prior_std;

  /// When it has rows: the calibration configurations (actuators) and which readings are
  /// taken (a NaN reading is not taken, anything else is simulated), e.g. from experiment
  /// design, instead of random draws. num_configurations must equal its number of rows, and
  /// it must have one column per actuator and per reading (make_scenario throws
  /// std::invalid_argument naming the size that differs). Every row must be reachable with
  /// the true parameters.
  Measurements planned;

  /// When it has num_parameters entries: the true parameter values (a known truth, e.g. a
  /// model file), instead of nominal + drawn errors on the free parameters.
  VectorXd truth;

  /// The parameter error, noise, prior std (0 for a unit not given) and range (NaN for a
  /// unit not given) for `unit`.
  double param_error_for(const std::string& unit) const;
  double noise_for(const std::string& unit) const;
  double config_range_for(const std::string& unit) const;
  double prior_std_for(const std::string& unit) const;
};

/// The paper's Table 2: case 1..5 -> noise half-width and number of configurations.
struct PaperCase {
  int id;
  double noise_half_width;
  int num_configurations;
};
const std::vector<PaperCase>& paper_cases();
/// Throws std::invalid_argument for an id outside 1..5.
const PaperCase& paper_case(int id);

struct Scenario {
  std::shared_ptr<const MeasurementModel> model;
  ScenarioOptions options;
  VectorXd nominal;                    ///< full parameter vector, nominal values
  VectorXd truth;                      ///< full parameter vector, true values
  std::vector<int> free_indices;       ///< the estimated parameters
  VectorXd home_actuators;             ///< actuator values at home (nominal model)
  VectorXd actuator_ranges;            ///< half-width of the configuration box, per actuator
  Measurements calibration;            ///< noisy readings for the calibration
  MatrixXd validation_actuators;       ///< num_validation x num_actuators
  std::vector<Pose> validation_poses;  ///< true poses of the validation configurations

  /// The least-squares problem of this scenario, starting from the nominal values.
  std::shared_ptr<CalibrationProblem> make_problem() const;
};

/// Draws a scenario. Configurations whose true forward kinematics fails are redrawn (from
/// the same stream, so the result is still a function of the seed). A model with readings in
/// both mm and rad that states no reading std gets one from the noise (a / sqrt(3) per
/// unit, when both are > 0), so that the fit weighs each unit by its noise. With a prior
/// (ScenarioOptions::prior_std, or the model's own prior_std) it always gets one: the prior
/// weighs against whitened residuals.
Scenario make_scenario(std::shared_ptr<const MeasurementModel> model,
                       const ScenarioOptions& options);

/// Pose errors of the model with `params` against the true poses, over the validation set.
struct PoseErrorStats {
  double position_mean_mm = 0;
  double position_max_mm = 0;
  double orientation_mean_rad = 0;
  double orientation_max_rad = 0;
  int fk_failures = 0;  ///< validation configurations where forward kinematics failed
};
PoseErrorStats validation_errors(const Scenario& scenario, const VectorXd& params);

/// One simulated calibration with its accuracy at every iteration.
struct CalibrationRun {
  Summary summary;
  VectorXd estimate;  ///< full parameter vector
  PoseErrorStats before;
  PoseErrorStats after;
  /// Validation errors at each trace entry (same length as summary.trace).
  std::vector<PoseErrorStats> trace_errors;
  /// RMS of (estimate - truth) over the free parameters of each unit (angles wrapped).
  UnitValues parameter_rms_errors;
  /// Its mm and rad values (0 when no free parameter is in that unit).
  double parameter_rms_error = 0;
  double parameter_rms_error_rad = 0;
  /// Wall time of the solve alone: summary.wall_seconds minus the time spent computing the
  /// per-iteration validation errors inside the callback (summary.trace[k].seconds are
  /// corrected the same way; summary.wall_seconds is left as measured). When a failed implicit
  /// solve was replaced by the nested one (formulation_note), its time is included: both
  /// solves are what the calibration took, while summary and trace are the nested solve's.
  double solve_seconds = 0;
  /// The formulation solved, and why the requested one was not (empty when it was).
  Formulation formulation = Formulation::kNested;
  std::string formulation_note;
};

/// Solves the scenario's problem from nominal, or from `start` (free parameters) when given:
/// the MAP estimate when a free parameter has a prior (Parameter::prior_std, set by
/// ScenarioOptions::prior_std), else least squares. When `track_iterations` is set, the
/// validation errors are computed at every iteration (through the solver's callback).
/// `formulation`: nested or implicit (calibration_solve.hpp).
CalibrationRun run_calibration(const Scenario& scenario, const Solver& solver,
                               SolverOptions options, bool track_iterations = true,
                               Formulation formulation = Formulation::kNested,
                               const VectorXd& start = VectorXd());

/// The spread of the scenario's errors (ScenarioOptions::param_error_for, or a parameter's
/// own error_half_width): where kincal simulate --starts draws its starts.
StartSpread scenario_start_spread(const Scenario& scenario);

/// The starts of kincal simulate --starts: the scenario's problem (with its prior, if any)
/// solved from nominal and from starts - 1 draws of scenario_start_spread, seeded by the
/// scenario's seed, on `threads` threads (0 = all cores).
MultiStartResult solve_scenario_starts(const Scenario& scenario, const Solver& solver,
                                       const SolverOptions& options, int starts, int threads = 0);

/// The run's residuals against the noise the simulation drew (uniform, std a / sqrt(3) per
/// unit): FitCheck's chi-square on m - n degrees of freedom, which flags a run that stopped in
/// a local minimum. Not tested with a prior, without noise in a reading's unit, or without
/// degrees of freedom.
FitCheck simulated_fit_check(const Scenario& scenario, const CalibrationRun& run);

}  // namespace kincal
