#pragma once
// The simulate workflow: one simulated calibration of a model. True parameters drawn around
// the nominal ones (or given), configurations drawn at random, chosen by experiment design or
// given, readings simulated with noise, the calibrate workflow's identifiability check, the
// solve (one start or several) and the pose errors before and after on validation
// configurations. What `kincal simulate` does between parsing its options and writing its
// files, as one library call.
//
//   kincal::SimulateRequest request;
//   request.model = kincal::make_preset("cube-hexapod");
//   request.scenario.num_configurations = 30;
//   request.scenario.noise_half_width = 0.00125;     // mm
//   const kincal::SimulateResult r = kincal::simulate(request);
//   std::cout << kincal::simulation_text(r);

#include <functional>
#include <memory>
#include <optional>
#include <string>
#include <vector>

#include <nlohmann/json.hpp>

#include "kincal/framework/calibration/calibration_solve.hpp"
#include "kincal/framework/calibration/multi_start.hpp"
#include "kincal/framework/calibration/simulation.hpp"
#include "kincal/framework/design/experiment_design.hpp"
#include "kincal/framework/least_squares/solver.hpp"

namespace kincal {

struct SimulateRequest {
  /// The model simulated: its nominal values, free mask and priors (a per-unit prior is
  /// scenario.prior_std / prior_std_rad instead). Not modified.
  std::shared_ptr<const MeasurementModel> model;
  /// Configurations, noise, parameter errors, validation, seed; `truth` and `planned` when
  /// the true model or the configurations are given.
  ScenarioOptions scenario;
  /// The backend (null: the registry's "lm") and its settings.
  std::shared_ptr<const Solver> solver;
  SolverOptions solver_options;
  std::optional<Formulation> formulation;  ///< unset: default_formulation(model)
  int starts = 1;
  /// Fix what the simulated data cannot determine instead of stopping.
  bool allow_rank_deficient = false;
  /// Choose the configurations by experiment design on the nominal model with this criterion
  /// (scenario.num_configurations of them, from `design_candidates` random candidates).
  std::optional<DesignCriterion> design;
  int design_candidates = 10000;
  /// In the report: the preset's name or the model file's path, the paper's case (0: none),
  /// the files the configurations and the truth came from (empty: drawn).
  std::string model_name = "cube-hexapod";
  int case_id = 0;
  std::string configs_file, truth_file;
  /// How the face names its options in messages: "--" for the program ("--poses 4: ..."),
  /// "" for Python ("poses 4: ...").
  std::string option_prefix = "--";
  /// The face's prior option was given: the scenario's prior errors name it.
  bool priors_given = false;
  /// What to say after a rank deficiency when the call stops on it.
  std::string rank_deficiency_remedy =
      "widen the configuration range, measure more poses, fix parameters, or allow the rank "
      "deficiency";
  /// Called with each note as it arises (they are in SimulateResult::notes as well).
  std::function<void(const std::string&)> on_note;
};

struct SimulateResult {
  Scenario scenario;
  CalibrationRun run;
  StartsReport starts;
  /// Free parameters the simulated data cannot determine, fixed at their nominal values.
  std::vector<std::string> fixed_by_identifiability;
  /// The design's description when the configurations were chosen by design, else empty.
  std::string design_text;
  std::vector<std::string> notes;
  /// The solver reached a solution (converged, or stopped at its iteration limit).
  bool solved = false;
  /// The request's names, for the renderings.
  std::string model_name, configs_file, truth_file;
  int case_id = 0;
};

/// A scenario as a user writes it: quantities per unit as text ("5mm,0.01rad"; a bare number
/// is mm), the paper's case, counts and seed.
struct ScenarioText {
  int case_id = 0;           ///< the paper's Table 2 case 1..5 (sets poses and the noise); 0: none
  std::optional<int> poses;  ///< configurations measured; unset: the case's, or 30
  std::optional<std::string> noise_half_width;  ///< U[-a, a] per unit; unset: 0 (or the case's)
  std::optional<std::string> noise_std;         ///< the same noise as its std (a / sqrt(3))
  std::string param_error = "5mm,0.01rad";      ///< "0": zero in every unit (the truth is nominal)
  std::optional<std::string> config_range;      ///< unset: each actuator's range in the model
  std::uint64_t seed = 1;
  int validation = 200;
};

/// The ScenarioOptions of `text`. Throws std::invalid_argument naming the option as the face
/// spells it (`option_prefix` "--": "--poses must be at least 1"; "": "poses must be ...").
ScenarioOptions scenario_options(const ScenarioText& text, const std::string& option_prefix);

/// The rows of a configurations file as ScenarioOptions::planned: their actuator values, and
/// the readings to simulate: a row without any reading (a design template) takes every
/// reading, a row with some takes those.
Measurements planned_rows(Measurements rows);

/// Runs the workflow (see the file's comment). Throws std::invalid_argument for a request
/// that cannot be simulated: a prior per unit missing a free parameter's unit, configurations
/// the truth cannot reach, fewer readings than free parameters, or (without
/// allow_rank_deficient) simulated data that cannot determine every free parameter. A solve
/// that fails is a result (solved false), not an exception.
SimulateResult simulate(const SimulateRequest& request);

/// The program's renderings: the text report, the JSON report ("kincal-simulate"), the
/// per-iteration trace (CSV), and the simulated measurements as a measurement file whose
/// comment names the truth file `truth_path` and the SHA-256 of its text `truth_text`.
std::string simulation_text(const SimulateResult& result);
nlohmann::json simulation_json(const SimulateResult& result);
std::string simulation_trace_csv(const CalibrationRun& run);
/// The true model's file text (model_io's JSON, written by the face: models/ is above this
/// layer) goes in as `truth_text`.
std::string simulated_data_csv(const SimulateResult& result, const std::string& truth_path,
                               const std::string& truth_text);

/// The JSON of pose errors and of one simulated calibration (without the workflow's own
/// sections); `model_name` the preset's name or the model file's path.
nlohmann::json to_json(const PoseErrorStats& stats);
nlohmann::json to_json(const Scenario& scenario, const CalibrationRun& run, int case_id,
                       const std::string& model_name);

}  // namespace kincal
