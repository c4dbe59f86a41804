#pragma once
// The calibrate workflow: a model's free parameters estimated from measurements, with what a
// user needs to decide whether to load the result. What `kincal calibrate` does between
// reading its files and writing them, as one library call: no argv, no file, no printing.
//
//   kincal::CalibrateRequest request;
//   request.model = model;                 // nominal values, free mask, priors, reading_std
//   request.measurements = kincal::load_measurements("data.csv", *model, nominal);
//   const kincal::CalibrateResult result = kincal::calibrate(request);
//   if (result.solved) use(result.parameters);   // result.verdict says whether to load them
//
// In order: the request is checked (throws std::invalid_argument naming what is wrong, before
// any solve); the data's identifiability at the start decides which free parameters are
// solved for (the ones the data cannot determine are fixed and named, or the call throws,
// per `when_rank_deficient`); the solve (one start, or several: `starts`); an equivalent
// solution is mapped back to the branch nearest the nominal values; the report (uncertainty,
// identifiability, fit, residual structure), the baselines (nominal, registration only,
// cross-validation) and the verdict. A solve that fails is a result (solved false, the
// summary says why), not an exception.

#include <cstdint>
#include <functional>
#include <memory>
#include <optional>
#include <string>
#include <vector>

#include "kincal/framework/analysis/calibration_report.hpp"
#include "kincal/framework/analysis/calibration_verdict.hpp"
#include "kincal/framework/analysis/geometry_only.hpp"
#include "kincal/framework/analysis/identifiability_check.hpp"
#include "kincal/framework/analysis/target_accuracy.hpp"
#include "kincal/framework/calibration/calibration_solve.hpp"
#include "kincal/framework/calibration/measurement_loading.hpp"
#include "kincal/framework/calibration/multi_start.hpp"
#include "kincal/framework/least_squares/robust_loss.hpp"
#include "kincal/framework/least_squares/solver.hpp"

namespace kincal {

struct CalibrateRequest {
  /// The model: its nominal values are the start, its free mask what is estimated, its
  /// prior_std and reading_std the prior and the weights. Not modified.
  std::shared_ptr<const MeasurementModel> model;
  /// The measurements for `model` (load_measurements, or built in memory with `lines` left
  /// empty: rows are then named by their position, from 1).
  LoadedMeasurements measurements;
  /// The backend (null: the registry's "lm") and its settings. The options' callback sees
  /// every iteration and may stop the solve (Ctrl-C in the program).
  std::shared_ptr<const Solver> solver;
  SolverOptions solver_options;
  /// nested or implicit (calibration_solve.hpp); unset: default_formulation(model).
  std::optional<Formulation> formulation;
  IdentifiabilityOptions identifiability;
  WhenRankDeficient when_rank_deficient = WhenRankDeficient::kStop;
  /// What to say, after the deficiency, when the call stops on it (kStop).
  std::string rank_deficiency_remedy = "fix the parameters the data cannot determine";
  /// K-fold cross-validation of the calibration and the registration-only fit (0: none,
  /// else at least 2 and at most one fold per configuration).
  int folds = 0;
  /// Solves from this many starting values: the model's, and the others drawn around them
  /// from each free parameter's tolerance, reproducibly from `seed`.
  int starts = 1;
  std::uint64_t seed = 1;
  /// Priors from the model's stated tolerances (param_error: a uniform error of half-width e
  /// has std e / sqrt(3)) on the free parameters that state one: kAuto (the default) when a
  /// sensor asks for them (Sensor::takes_tolerance_priors_by_default: a camera) and no
  /// parameter of the model has a prior_std; kOn whenever tolerances are stated (a prior_std
  /// given stays); kOff never. What was done is a note.
  enum class TolerancePriors { kAuto, kOn, kOff };
  TolerancePriors tolerance_priors = TolerancePriors::kAuto;
  /// Calibration in steps (as ROS robot_calibration's calibration_steps): before the solve,
  /// each step solves for the free parameters matching its glob patterns only ("camera.*"),
  /// the others at their current values, each from where the previous step left them; the
  /// solve of every free parameter then starts there. The prior stays centred on the nominal
  /// values, so the steps change where the solve starts, not what it estimates. A step that
  /// frees none of the free parameters is an error; what each step did is a note. Empty:
  /// one solve.
  std::vector<std::vector<std::string>> steps;
  /// Names of the inputs, in messages and in the report only; may be empty.
  std::string model_file, data_file;
  /// Called with each note as it arises (they are in CalibrateResult::notes as well), so that
  /// a terminal shows them in order with other output; may be empty.
  std::function<void(const std::string&)> on_note;
};

/// A step of CalibrateRequest::steps from its text: glob patterns separated by commas
/// ("camera.*,*.offset"); throws std::invalid_argument naming `option` for an empty one.
std::vector<std::string> parse_calibration_step(const std::string& text, const std::string& option);

/// "auto", "on" or "off"; throws std::invalid_argument naming `option` for anything else.
CalibrateRequest::TolerancePriors parse_tolerance_priors(const std::string& text,
                                                         const std::string& option);

/// `model` with priors from its stated tolerances as `choice` asks for (see
/// CalibrateRequest::tolerance_priors): the same model when none applies; `note` (when
/// non-null) says what was done, or is left empty.
std::shared_ptr<const MeasurementModel> with_tolerance_priors(
    std::shared_ptr<const MeasurementModel> model, CalibrateRequest::TolerancePriors choice,
    std::string* note);

struct CalibrateResult {
  /// The solver reached a solution (converged, or stopped at its iteration limit): the
  /// parameters, report and verdict describe an estimate. Otherwise summary says why not.
  bool solved = false;
  Summary summary;
  /// Every parameter of the model (fixed ones at their nominal values) at the estimate.
  VectorXd parameters;
  /// The parameters solved for (indices in the model), and the free ones the data could not
  /// determine, fixed at their nominal values, each with what it duplicates in words.
  std::vector<int> free;
  std::vector<std::string> fixed_by_identifiability;
  std::vector<std::string> null_directions;
  std::vector<std::string> fixed_effects;  ///< per fixed: dependent_effect
  CalibrationReport report;
  StartsReport starts;
  CalibrationVerdict verdict;
  /// What a user should read, in order: the loading's notes, then the workflow's.
  std::vector<std::string> notes;
  /// What a kinematic export leaves uncorrected at the measured configurations, when the
  /// model has non-geometric parameters (joint compliance) not all zero.
  std::optional<GeometryOnlyEffect> geometry_only;
};

/// The checks of a request that need no data, for a caller that wants them before it reads
/// any (calibrate makes them again): `model` has free parameters; a prior on them has
/// reading_std to be weighed against; no robust loss with a prior. Returns whether the model
/// states a prior on a free parameter. Throws std::invalid_argument naming `model_file`.
bool check_calibration_model(const MeasurementModel& model, const RobustLoss& loss,
                             const std::string& model_file);

/// The robust loss `text` ("huber:0.02", "cauchy:1") parsed into `options.loss` for `solver`,
/// which must take one. Throws std::invalid_argument "<option> '<text>': <why>" for a
/// malformed loss, and "<option>: solver '<solver_name>' does not take a robust loss (<why>);
/// <remedy>" for a backend without one. `option` is how the face names it ("--loss", "loss").
void add_robust_loss(const std::string& text, const Solver& solver, const std::string& solver_name,
                     SolverOptions& options, const std::string& option, const std::string& remedy);

/// `target` judged against the calibration's predicted pose error (judge_predicted_target);
/// a target the calibration does not meet adds a do-not-load finding to `result.verdict`, so
/// that every report and the program's exit code say so.
TargetJudgement judge_calibration_target(CalibrateResult& result, const TargetAccuracy& target);

/// Runs the calibrate workflow (see the file's comment). Throws std::invalid_argument for a
/// request that cannot be solved: no free parameter, fewer readings than free parameters,
/// a prior without reading_std, a prior with a robust loss, more folds than configurations,
/// readings whose sum of squares overflows at the start, or (kStop) parameters the data
/// cannot determine.
CalibrateResult calibrate(const CalibrateRequest& request);

}  // namespace kincal
