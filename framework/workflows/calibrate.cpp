#include "kincal/framework/workflows/calibrate.hpp"

#include <cmath>
#include <cstdio>
#include <numeric>
#include <stdexcept>

#include "kincal/framework/analysis/calibration_baselines.hpp"
#include "kincal/framework/base/format_text.hpp"
#include "kincal/framework/calibration/constrained_problem.hpp"
#include "kincal/framework/calibration/data_checks.hpp"
#include "kincal/framework/calibration/equivalent_solutions.hpp"
#include "kincal/framework/calibration/prior_and_noise.hpp"
#include "kincal/framework/calibration/prior_problem.hpp"
#include "kincal/framework/least_squares/solver_registry.hpp"

namespace kincal {

namespace {

// The readings at the starting values must give a finite cost: a reading such as 1e308 is a
// number but makes ½|r|² overflow, and the solver could only say that it failed at the
// start. Names the line with the largest residual.
void check_cost_is_finite(const std::string& data_file, const VectorXd& r,
                          const std::vector<int>& lines, int readings_per_row,
                          const std::vector<std::string>& reading_names) {
  if (std::isfinite(0.5 * r.squaredNorm())) return;
  Eigen::Index worst = 0;
  r.cwiseAbs().maxCoeff(&worst);
  const int row = static_cast<int>(worst) / readings_per_row;
  char residual[32];
  std::snprintf(residual, sizeof residual, "%.3g", r[worst]);
  throw std::invalid_argument(data_file + ":" + std::to_string(lines[row]) + ": field '" +
                              reading_names[worst % readings_per_row] +
                              "': predicted - measured is " + residual +
                              " at the model's values, which makes the sum of squares overflow; "
                              "expected readings on the scale of the machine");
}

// Rows without a file line are named by their position, from 1.
std::vector<int> row_lines(const LoadedMeasurements& loaded) {
  if (!loaded.lines.empty()) return loaded.lines;
  std::vector<int> lines(static_cast<std::size_t>(loaded.data.size()));
  std::iota(lines.begin(), lines.end(), 1);
  return lines;
}

// The request's checks that need the data, before any solve.
void check_data_size(const CalibrateRequest& request, int configurations, std::size_t free) {
  const LoadedMeasurements& loaded = request.measurements;
  if (request.folds == 1 || request.folds < 0)
    throw std::invalid_argument(
        "folds must be 0 or at least 2 (the number of cross-validation folds)");
  if (request.folds > configurations)
    throw std::invalid_argument("--folds " + std::to_string(request.folds) +
                                ": more folds than the " + std::to_string(configurations) +
                                " configurations of " + request.data_file);
  const int readings = configurations * request.model->num_readings();
  if (readings < static_cast<int>(free))
    throw std::invalid_argument(
        request.data_file + ": " + std::to_string(configurations) + " usable configurations" +
        (loaded.duplicate_rows > 0 ? " (" + std::to_string(loaded.duplicate_rows) +
                                         " more row(s) copy one exactly and count once)"
                                   : std::string()) +
        " give " + std::to_string(readings) + " readings for " + std::to_string(free) +
        " free parameters; expected at least as many readings as free parameters "
        "(measure more configurations or --fix parameters)");
}

}  // namespace

bool check_calibration_model(const MeasurementModel& model, const RobustLoss& loss,
                             const std::string& model_file) {
  const bool with_prior = check_prior_usable(model, model_file);
  if (with_prior && loss.kind != RobustLoss::Kind::kNone)
    throw std::invalid_argument(
        "--loss " + loss.to_string() +
        " with a prior (prior_std, --prior-std): not supported (the backend would "
        "robustify the prior's residuals too); calibrate with one or the other");
  if (model.parameters().free_indices().empty())
    throw std::invalid_argument("no free parameters: nothing to calibrate (use --free)");
  return with_prior;
}

void add_robust_loss(const std::string& text, const Solver& solver, const std::string& solver_name,
                     SolverOptions& options, const std::string& option, const std::string& remedy) {
  try {
    options.loss = RobustLoss::parse(text);
  } catch (const std::invalid_argument& e) {
    throw std::invalid_argument(option + " '" + text + "': " + e.what());
  }
  try {
    solver.check_options(options);
  } catch (const InvalidSolverOptions& e) {
    throw std::invalid_argument(option + ": solver '" + solver_name +
                                "' does not take a robust loss (" + e.what() + "); " + remedy);
  }
}

CalibrateRequest::TolerancePriors parse_tolerance_priors(const std::string& text,
                                                         const std::string& option) {
  if (text == "auto") return CalibrateRequest::TolerancePriors::kAuto;
  if (text == "on") return CalibrateRequest::TolerancePriors::kOn;
  if (text == "off") return CalibrateRequest::TolerancePriors::kOff;
  throw std::invalid_argument(option + " '" + text + "': expected auto, on or off");
}

std::shared_ptr<const MeasurementModel> with_tolerance_priors(
    std::shared_ptr<const MeasurementModel> model, CalibrateRequest::TolerancePriors choice,
    std::string* note) {
  using Choice = CalibrateRequest::TolerancePriors;
  if (note) note->clear();
  if (choice == Choice::kOff) return model;
  const ParameterSet& parameters = model->parameters();
  if (choice == Choice::kAuto) {
    bool asked = false;
    for (const auto& sensor : model->sensors())
      asked = asked || sensor->takes_tolerance_priors_by_default();
    if (!asked) return model;
    for (int i = 0; i < parameters.size(); ++i)
      if (parameters[i].has_prior()) return model;  // the user's priors stand
  }
  // A prior is weighed against the readings' noise: without it stated, the default says why
  // it does not apply (on, asked for, fails in check_calibration_model with the remedy).
  if (choice == Choice::kAuto && !model->weighted()) {
    int stated = 0;
    for (int i : parameters.free_indices())
      stated += parameters[i].error_half_width > 0 && std::isfinite(parameters[i].error_half_width);
    if (stated > 0 && note)
      *note =
          "no priors from the stated tolerances, the default with a camera: the readings' "
          "noise std is not stated to weigh them against (give --noise-std, e.g. 0.2px, or "
          "reading_std in the model file)";
    return model;
  }
  auto copy = std::make_shared<MeasurementModel>(*model);
  int count = 0;
  for (int i : parameters.free_indices()) {
    const Parameter& p = parameters[i];
    if (p.has_prior() || !(p.error_half_width > 0) || !std::isfinite(p.error_half_width)) continue;
    const double std = p.error_half_width / std::sqrt(3.0);
    copy->parameters().for_each_matching(p.name, [std](Parameter& q) { q.prior_std = std; });
    ++count;
  }
  if (count == 0) return model;
  if (note)
    *note = "priors from the stated tolerances (param_error, std = half-width / sqrt(3)) on " +
            std::to_string(count) + " free parameter(s)" +
            (choice == Choice::kAuto
                 ? ": the default with a camera, so that the fit does not move a good robot to "
                   "absorb the camera's errors (tolerance priors off to fit without them)"
                 : "");
  return copy;
}

namespace {

// The start of the solve after the steps of request.steps (see there), as free parameters
// `free`; each step's outcome is said.
VectorXd solve_steps(const CalibrateRequest& request,
                     const std::shared_ptr<const MeasurementModel>& model, const Measurements& data,
                     const VectorXd& nominal, const std::vector<int>& free, const Solver& solver,
                     const SolverOptions& options,
                     const std::function<void(const std::string&)>& say) {
  const ParameterSet& parameters = model->parameters();
  VectorXd current = nominal;
  const int count = static_cast<int>(request.steps.size());
  for (int k = 0; k < count; ++k) {
    const std::vector<std::string>& patterns = request.steps[k];
    std::string named;
    for (const std::string& p : patterns) named += (named.empty() ? "" : " ") + p;
    std::vector<int> step_free;
    for (int i : free)
      for (const std::string& p : patterns)
        if (glob_match(p, parameters[i].name)) {
          step_free.push_back(i);
          break;
        }
    if (step_free.empty())
      throw std::invalid_argument("calibrate: step " + std::to_string(k + 1) + " (" + named +
                                  ") frees none of the free parameters");
    const CalibrationProblem step(model, data, current, step_free);
    Prior prior = model_prior(step);
    for (std::size_t j = 0; j < step_free.size(); ++j)
      prior.mean[static_cast<int>(j)] = nominal[step_free[j]];  // the prior stays at nominal
    VectorXd x = step.initial_free_parameters();
    const CalibrationSolve solved =
        solve_calibration(solver, step, prior, x, options, Formulation::kNested);
    current = step.full_parameters(x);
    say(format_text(
        "step %d of %d (%s): %d parameters, cost %.6g -> %.6g (%s)", k + 1, count, named.c_str(),
        static_cast<int>(step_free.size()), solved.summary.initial_cost, solved.summary.final_cost,
        reached_solution(solved.summary) ? "converged"
                                         : ("not converged: " + solved.summary.message).c_str()));
  }
  VectorXd start(free.size());
  for (std::size_t i = 0; i < free.size(); ++i) start[static_cast<int>(i)] = current[free[i]];
  return start;
}

}  // namespace

std::vector<std::string> parse_calibration_step(const std::string& text,
                                                const std::string& option) {
  std::vector<std::string> patterns;
  std::string::size_type start = 0;
  while (true) {
    const auto comma = text.find(',', start);
    std::string p =
        text.substr(start, comma == std::string::npos ? std::string::npos : comma - start);
    p.erase(0, p.find_first_not_of(" \t"));
    p.erase(p.find_last_not_of(" \t") + 1);
    if (p.empty())
      throw std::invalid_argument(option + " '" + text +
                                  "': expected glob patterns of parameter names separated by "
                                  "commas (camera.*,*.offset)");
    patterns.push_back(p);
    if (comma == std::string::npos) break;
    start = comma + 1;
  }
  return patterns;
}

CalibrateResult calibrate(const CalibrateRequest& request) {
  if (!request.model) throw std::invalid_argument("calibrate: the request has no model");
  if (request.starts < 1) throw std::invalid_argument("calibrate: starts must be at least 1");
  // A robust loss and a prior do not go together (check_calibration_model): the default
  // gives way to the loss the user chose.
  using Choice = CalibrateRequest::TolerancePriors;
  const bool robust = request.solver_options.loss.kind != RobustLoss::Kind::kNone;
  std::string tolerance_note;
  const std::shared_ptr<const MeasurementModel> model = with_tolerance_priors(
      request.model,
      robust && request.tolerance_priors == Choice::kAuto ? Choice::kOff : request.tolerance_priors,
      &tolerance_note);
  const bool with_prior =
      check_calibration_model(*model, request.solver_options.loss, request.model_file);
  std::shared_ptr<const Solver> solver = request.solver;
  if (!solver) solver = SolverRegistry::global().create("lm");
  SolverOptions options = request.solver_options;
  solver->check_options(options);
  // The report records every setting in force, the backend's defaults included.
  options.backend = solver->settings_in_force(options);

  CalibrateResult result;
  const auto say = [&](const std::string& text) {
    result.notes.push_back(text);
    if (request.on_note) request.on_note(text);
  };
  if (!tolerance_note.empty()) say(tolerance_note);
  const LoadedMeasurements& loaded = request.measurements;
  const Measurements& data = loaded.data;
  const std::vector<int> lines = row_lines(loaded);
  const VectorXd nominal = model->parameters().nominal_values();
  std::vector<int> free = model->parameters().free_indices();

  // A wrong home_pose gives other valid poses: say so when the data lands far from it.
  const HomePoseCheck home_check = check_poses_near_home(*model, nominal, data);
  if (home_check.far) say(home_check.warning);
  check_data_size(request, data.size(), free.size());
  if (!loaded.copied_rows_note.empty()) say(loaded.copied_rows_note);

  // Identifiability at the starting point decides whether solving makes sense at all.
  {
    const CalibrationProblem probe(model, data, nominal, free);
    VectorXd r;
    MatrixXd J;
    std::string why;
    if (!probe.evaluate(probe.initial_free_parameters(), &r, &J, &why))
      throw std::invalid_argument(request.data_file + ": " + why);
    check_cost_is_finite(request.data_file, r, lines, model->num_readings(),
                         model->reading_names());
    append_constraint_rows(probe, probe.initial_free_parameters(), J);
    IdentifiabilityCheck check =
        check_identifiability(request.data_file, probe, J, request.when_rank_deficient,
                              request.identifiability, request.rank_deficiency_remedy);
    for (const std::string& text : check.notes) say(text);
    free = std::move(check.free);
    result.fixed_by_identifiability = std::move(check.fixed);
    result.null_directions = std::move(check.null_directions);
    result.fixed_effects = std::move(check.fixed_effects);
  }
  if (data.size() * model->num_readings() == static_cast<int>(free.size()))
    say("as many readings as free parameters: the fit is exact and the "
        "standard deviations cannot be estimated");

  const CalibrationProblem problem(model, data, nominal, free);
  VectorXd x = problem.initial_free_parameters();
  const Prior prior = model_prior(problem);
  if (!request.steps.empty())
    x = solve_steps(request, model, data, nominal, free, *solver, options, say);
  const Formulation requested =
      request.formulation ? *request.formulation : default_formulation(*model);
  // With a prior: the MAP estimate, through the same backend (docs/theory.md). Whatever the
  // formulation, the report below is the nested problem's at x.
  Formulation solved_formulation = Formulation::kNested;
  std::string formulation_note;
  if (request.starts > 1) {
    if (requested == Formulation::kImplicit && request.formulation)
      formulation_note = "implicit formulation not used (--starts solves the nested one)";
    // Tolerances as the nominal-accuracy prediction assumes them (pose_accuracy.hpp). The
    // starts solve the nested problem, with the model's constraints and the prior.
    MultiStartOptions multi;
    multi.starts = request.starts;
    multi.threads = options.num_threads;
    multi.seed = request.seed;
    multi.spread = model_start_spread(*model, free, 5.0, 0.01);
    with_nested_problem(problem, prior, [&](const LeastSquaresProblem& solved_problem) {
      result.starts.result = solve_multi_start(solved_problem, *solver, x, options, multi);
    });
    result.starts.seed = multi.seed;
    result.starts.spread_from = multi.spread.assumed
                                    ? "the tolerances (param_error, else prior_std, else an "
                                      "assumed ±5 mm and ±0.01 rad)"
                                    : "the tolerances (param_error, else prior_std)";
    result.starts.spread_assumed = multi.spread.assumed;
    x = result.starts.result.starts[result.starts.result.best_start].x;
    result.summary = result.starts.result.estimate_summary();
  } else {
    const VectorXd start = x;
    CalibrationSolve solution = solve_calibration(*solver, problem, prior, x, options, requested);
    formulation_note = std::move(solution.note);
    result.summary = std::move(solution.summary);
    solved_formulation = solution.formulation;
    result.starts = single_start_report(start, x, result.summary, request.seed);
  }

  // An equivalent solution away from the nominal values (whole turns, a flipped link) is
  // mapped back when the map is exact; what stays far from nominal is a finding below.
  const NominalBranch branch = map_to_nominal_branch(problem, x);
  x = branch.x;
  CalibrationReport& report = result.report;
  report = make_calibration_report(problem, x, result.summary, lines, options.loss,
                                   request.identifiability,
                                   prior.any() ? prior.precision() : VectorXd());
  report.branch_mapped = branch.mapped;
  report.branch_rejected = branch.rejected;
  report.duplicate_rows = loaded.duplicate_rows;
  report.repeated_configurations = loaded.repeated_configurations;
  report.repeat_rows = loaded.repeat_rows;
  if (!formulation_note.empty()) say(formulation_note);
  report.solver_options = options;
  report.solver_options.callback = nullptr;
  report.formulation = to_string(solved_formulation);
  report.formulation_note = formulation_note;
  report.model_file = request.model_file;
  report.data_file = request.data_file;
  report.fixed_by_identifiability = result.fixed_by_identifiability;
  report.fixed_effects = result.fixed_effects;
  report.skipped_lines = loaded.skipped_lines;
  report.dropped_readings = loaded.dropped_readings;
  if (home_check.far) report.warnings.push_back(home_check.warning);

  result.solved = reached_solution(result.summary);
  if (result.solved)
    add_calibration_baselines(report, model, data, nominal, free, *solver, options, with_prior,
                              request.folds, request.identifiability);
  result.parameters = problem.full_parameters(x);
  result.free = std::move(free);
  result.verdict = judge_calibration(report);
  if (result.solved) result.geometry_only = geometry_only_effect(*model, result.parameters, data);
  return result;
}

TargetJudgement judge_calibration_target(CalibrateResult& result, const TargetAccuracy& target) {
  TargetJudgement judged = judge_predicted_target(target, result.report.predicted_accuracy);
  if (judged.meets == false)
    result.verdict.findings.push_back(
        {"target", Finding::Level::kDoNotLoad,
         "The calibration does not meet the target: " + judged.verdict + ".",
         "Measure more, or better chosen, configurations (kincal design --target), or state "
         "what you know as prior_std."});
  return judged;
}

}  // namespace kincal
