// kincal calibrate: estimates a model's free parameters from a measurement file and writes
// the calibrated model (same schema) and a report with uncertainty and identifiability.

#include <cmath>
#include <cstdio>
#include <iostream>
#include <optional>

#include "kincal/cli/common_options.hpp"
#include "kincal/cli/console.hpp"
#include "kincal/cli/html_report.hpp"
#include "kincal/cli/identifiability_check.hpp"
#include "kincal/cli/identifiability_words.hpp"
#include "kincal/cli/memory_check.hpp"
#include "kincal/cli/model_args.hpp"
#include "kincal/cli/sensitivity_option.hpp"
#include "kincal/cli/sha256.hpp"
#include "kincal/cli/shared_options.hpp"
#include "kincal/cli/starts_option.hpp"
#include "kincal/cli/target_accuracy.hpp"
#include "kincal/framework/analysis/calibration_baselines.hpp"
#include "kincal/framework/analysis/calibration_report.hpp"
#include "kincal/framework/analysis/calibration_verdict.hpp"
#include "kincal/framework/analysis/cross_validation.hpp"
#include "kincal/framework/analysis/position_error.hpp"
#include "kincal/framework/calibration/constrained_problem.hpp"
#include "kincal/framework/calibration/data_checks.hpp"
#include "kincal/framework/calibration/equivalent_solutions.hpp"
#include "kincal/framework/calibration/frame_turns.hpp"
#include "kincal/framework/calibration/prior_problem.hpp"
#include "kincal/framework/least_squares/robust_loss.hpp"
#include "kincal/models/model_io.hpp"

namespace kincal::cli {

namespace {

// The loss must reach the report (its name and the standard deviations depend on it), so it
// has one way in: --loss. A backend option would solve with it behind the report's back.
void reject_loss_as_solver_option(const po::variables_map& vm) {
  if (!vm.count("solver-option")) return;
  for (const auto& entry : vm["solver-option"].as<std::vector<std::string>>())
    if (entry.rfind("loss=", 0) == 0)
      throw CliError("--solver-option '" + entry + "': give the robust loss as --loss " +
                     entry.substr(5) +
                     " (calibrate reports the loss and uses it for the standard deviations)");
}

// --loss, validated against the chosen backend and added to its options.
RobustLoss loss_option(const po::variables_map& vm, SolverChoice& choice) {
  if (!vm.count("loss")) return {};
  const std::string text = vm["loss"].as<std::string>();
  RobustLoss loss;
  try {
    loss = RobustLoss::parse(text);
  } catch (const std::invalid_argument& e) {
    throw CliError("--loss '" + text + "': " + e.what());
  }
  choice.options.backend_options["loss"] = text;
  try {
    choice.solver->check_options(choice.options);
  } catch (const InvalidSolverOptions& e) {
    throw CliError("--loss: solver '" + choice.name + "' does not take a robust loss (" + e.what() +
                   "); use --solver lm");
  }
  return loss;
}

// The files of this run: no output may be an input or the other output. Checked before
// the data is read, so a typo does not cost a solve.
OutputPlan plan_files(const po::variables_map& vm) {
  OutputPlan plan;
  for (const char* option : {"model", "data"})
    if (vm.count(option)) plan.input(std::string("--") + option, vm[option].as<std::string>());
  if (vm.count("out")) plan.output("--out", vm["out"].as<std::string>());
  const std::string report = json_output(vm);
  if (!report.empty()) plan.output("--json", report);
  if (vm.count("html")) plan.output("--html", vm["html"].as<std::string>());
  plan.check();
  return plan;
}

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
  throw CliError(data_file + ":" + std::to_string(lines[row]) + ": field '" +
                 reading_names[worst % readings_per_row] + "': predicted - measured is " +
                 residual +
                 " at the model's values, which makes the sum of squares overflow; "
                 "expected readings on the scale of the machine");
}

// The calibrated model file. It lists what this run estimated as free: a model written after
// --allow-rank-deficient must not stop again on the parameters that had to be fixed.
std::string calibrated_model_text(const std::string& path, MeasurementModel& model,
                                  const VectorXd& values, const std::vector<std::string>& fixed) {
  for (const auto& name : fixed) model.parameters().set_free(name, false);
  if (!fixed.empty())
    note("calibrate", path + ": lists only the " + std::to_string(model.parameters().num_free()) +
                          " estimated parameters as free (the " + std::to_string(fixed.size()) +
                          " fixed above are fixed there)");
  return model_to_json(model, values).dump(2) + "\n";
}

}  // namespace

int run_calibrate(const Args& args) {
  po::options_description options("kincal calibrate");
  options.add_options()("model", po::value<std::string>(), "model file (JSON): the nominal values")(
      "data", po::value<std::string>(), "measurement file (CSV)")(
      "out", po::value<std::string>(), "write the calibrated model (JSON, same schema) to FILE")(
      "html", po::value<std::string>(),
      "write the report for people to FILE: one self-contained HTML page with plots")(
      "loss", po::value<std::string>(),
      "robust loss huber:DELTA or cauchy:DELTA (mm) against outliers (lm and ceres)")(
      "skip-bad-rows", po::bool_switch(), "drop rows the model cannot reach instead of failing")(
      "folds", po::value<int>(),
      "K-fold cross-validation (K >= 2): configuration i is held out in fold i mod K, the "
      "calibration and the registration-only fit are repeated on the other folds, and the "
      "held-out errors are reported")(
      "rcond",
      po::value<double>()->default_value(IdentifiabilityOptions{}.rcond,
                                         default_text(IdentifiabilityOptions{}.rcond)),
      "numerical rank threshold relative to the largest scaled singular value");
  add_json_option(options, "the report");
  add_allow_rank_deficient_option(options);
  add_deprecated_alias(options, "report", "json", po::value<std::string>());
  add_free_fix_options(options);
  add_prior_std_option(options);
  add_noise_std_option(options,
                       "replaces the model's reading_std (weighs the readings against each "
                       "other and a prior, and scales the reported uncertainty)");
  add_solver_options(options);
  add_formulation_option(options);
  add_data_size_option(options);
  add_target_option(options);
  add_sensitivity_options(options);
  add_starts_option(options);
  options.add_options()("seed", po::value<Seed>()->default_value(Seed{1}, "1"),
                        "random seed for the starts of --starts");
  add_threads_option(options);
  po::variables_map vm;
  if (!parse_command_line("calibrate", args, options, vm)) return 0;
  const int starts = starts_option(vm);
  const std::optional<TargetAccuracy> target = target_option(vm);
  if (!vm.count("data")) throw CliError("--data FILE is required");
  IdentifiabilityOptions id_options;
  id_options.rcond = vm["rcond"].as<double>();
  if (!(id_options.rcond > 0 && id_options.rcond < 1)) throw CliError("--rcond must be in (0, 1)");

  const int folds = vm.count("folds") ? vm["folds"].as<int>() : 0;
  if (vm.count("folds") && folds < 2)
    throw CliError("--folds must be at least 2 (the number of cross-validation folds)");

  // Every check that does not need the data comes first, so a typo costs nothing.
  reject_loss_as_solver_option(vm);
  SolverChoice choice = make_solver_choice(vm);
  choice.options.num_threads = threads_option(vm);
  const RobustLoss loss = loss_option(vm, choice);
  const OutputPlan plan = plan_files(vm);

  const std::string model_file = vm.count("model") ? vm["model"].as<std::string>() : "";
  const std::string data_file = vm["data"].as<std::string>();
  std::shared_ptr<MeasurementModel> model = load_model_option(vm);
  apply_free_fix(vm, *model);
  apply_noise_std(vm, *model);
  apply_prior_std(vm, *model);
  const bool with_prior = check_prior_usable(*model, model_file);
  if (with_prior && loss.kind != RobustLoss::Kind::kNone)
    throw CliError("--loss " + loss.to_string() +
                   " with a prior (prior_std, --prior-std): not supported (the backend would "
                   "robustify the prior's residuals too); calibrate with one or the other");
  const VectorXd nominal = model->parameters().nominal_values();
  std::vector<int> free = model->parameters().free_indices();
  if (free.empty()) throw CliError("no free parameters: nothing to calibrate (use --free)");
  const LoadedData loaded =
      load_measurements("calibrate", data_file, *model, nominal, vm["skip-bad-rows"].as<bool>(),
                        model_file, data_limits(vm));
  check_memory(data_file, loaded.data.size(),
               model->num_readings() * solve_bytes_per_row(static_cast<int>(free.size())),
               "configuration");
  // A wrong home_pose gives other valid poses: say so when the data lands far from it.
  const HomePoseCheck home_check = check_poses_near_home(*model, nominal, loaded.data);
  if (home_check.far) note("calibrate", home_check.warning);
  if (folds > loaded.data.size())
    throw CliError("--folds " + std::to_string(folds) + ": more folds than the " +
                   std::to_string(loaded.data.size()) + " configurations of " + data_file);
  const int readings = loaded.data.size() * model->num_readings();
  if (readings < static_cast<int>(free.size()))
    throw CliError(
        data_file + ": " + std::to_string(loaded.data.size()) + " usable configurations" +
        (loaded.duplicate_rows > 0 ? " (" + std::to_string(loaded.duplicate_rows) +
                                         " more row(s) copy one exactly and count once)"
                                   : std::string()) +
        " give " + std::to_string(readings) + " readings for " + std::to_string(free.size()) +
        " free parameters; expected at least as many readings as free parameters "
        "(measure more configurations or --fix parameters)");
  note_copied_rows("calibrate", loaded);

  // Identifiability at the starting point decides whether solving makes sense at all.
  std::vector<std::string> fixed_by_identifiability;
  std::vector<std::string> null_directions;  // why each of them was fixed, in words
  {
    const CalibrationProblem probe(model, loaded.data, nominal, free);
    VectorXd r;
    MatrixXd J;
    std::string why;
    if (!probe.evaluate(probe.initial_free_parameters(), &r, &J, &why))
      throw CliError(data_file + ": " + why);
    check_cost_is_finite(data_file, r, loaded.lines, model->num_readings(), model->reading_names());
    append_constraint_rows(probe, probe.initial_free_parameters(), J);
    const IdentifiabilityCheck check = check_identifiability(
        "calibrate", data_file, probe, J,
        when_rank_deficient(*model, vm["allow-rank-deficient"].as<bool>(),
                            vm.count("free") || vm.count("fix")),
        id_options, "fix parameters with --fix, or pass --allow-rank-deficient");
    free = check.free;
    fixed_by_identifiability = check.fixed;
    null_directions = check.null_directions;
  }
  if (readings == static_cast<int>(free.size()))
    note("calibrate",
         "as many readings as free parameters: the fit is exact and the "
         "standard deviations cannot be estimated");

  const CalibrationProblem problem(model, loaded.data, nominal, free);
  VectorXd x = problem.initial_free_parameters();
  const Prior prior = model_prior(problem);
  // With a prior: the MAP estimate, through the same backend (docs/theory.md). Whatever the
  // formulation, the report below is the nested problem's at x.
  Summary summary;
  StartsReport starts_report;
  Formulation solved_formulation = Formulation::kNested;
  std::string formulation_note;
  if (starts > 1) {
    if (vm.count("formulation") && formulation_choice(vm, *model) == Formulation::kImplicit)
      formulation_note = "implicit formulation not used (--starts solves the nested one)";
    // Tolerances as the nominal-accuracy prediction assumes them (pose_accuracy.hpp). The
    // starts solve the nested problem, with the model's constraints and the prior.
    MultiStartOptions multi;
    multi.starts = starts;
    multi.threads = choice.options.num_threads;
    multi.seed = vm["seed"].as<Seed>().value;
    multi.spread = model_start_spread(*model, free, 5.0, 0.01);
    with_nested_problem(problem, prior, [&](const LeastSquaresProblem& solved_problem) {
      starts_report.result =
          solve_multi_start(solved_problem, *choice.solver, x, choice.options, multi);
    });
    starts_report.seed = multi.seed;
    starts_report.spread_from = multi.spread.assumed
                                    ? "the tolerances (param_error, else prior_std, else an "
                                      "assumed ±5 mm and ±0.01 rad)"
                                    : "the tolerances (param_error, else prior_std)";
    starts_report.spread_assumed = multi.spread.assumed;
    x = starts_report.result.starts[starts_report.result.best_start].x;
    summary = starts_report.result.estimate_summary();
  } else {
    const VectorXd start = x;
    CalibrationSolve solution = solve_calibration(*choice.solver, problem, prior, x, choice.options,
                                                  formulation_choice(vm, *model));
    formulation_note = std::move(solution.note);
    summary = std::move(solution.summary);
    solved_formulation = solution.formulation;
    starts_report = single_start_report(start, x, summary, vm["seed"].as<Seed>().value);
  }

  // An equivalent solution away from the nominal values (whole turns, a flipped link) is
  // mapped back when the map is exact; what stays far from nominal is a finding below.
  const NominalBranch branch = map_to_nominal_branch(problem, x);
  x = branch.x;
  CalibrationReport report =
      make_calibration_report(problem, x, summary, loaded.lines, loss, id_options,
                              prior.any() ? prior.precision() : VectorXd());
  report.branch_mapped = branch.mapped;
  report.branch_rejected = branch.rejected;
  report.duplicate_rows = loaded.duplicate_rows;
  report.repeated_configurations = loaded.repeated_configurations;
  report.repeat_rows = loaded.repeat_rows;
  if (!formulation_note.empty()) note("calibrate", formulation_note);
  report.solver_options = choice.options;
  report.solver_options.callback = nullptr;
  report.formulation = to_string(solved_formulation);
  report.formulation_note = formulation_note;
  report.model_file = model_file;
  report.data_file = data_file;
  report.fixed_by_identifiability = fixed_by_identifiability;
  report.skipped_lines = loaded.skipped_lines;
  report.dropped_readings = loaded.dropped_readings;
  if (home_check.far) report.warnings.push_back(home_check.warning);

  const bool solved = summary.termination == TerminationType::kConverged ||
                      summary.termination == TerminationType::kMaxIterations;
  if (solved)
    add_calibration_baselines(report, model, loaded.data, nominal, free, *choice.solver,
                              choice.options, with_prior, folds, id_options);
  const std::string report_file = json_output(vm);
  const bool report_to_stdout = (!report_file.empty() && plan.to_stdout("--json")) ||
                                (vm.count("html") && plan.to_stdout("--html"));
  // The free set as solved (identifiability may have fixed some): the others are "fixed".
  const std::optional<SensitivityResult> sensitivity =
      solved ? sensitivity_from_options(vm, model, problem.full_parameters(x), loaded.data, free)
             : std::nullopt;
  nlohmann::ordered_json report_json = to_json(report);
  report_json["starts"] = starts_json(starts_report);
  if (target)
    report_json["target"] =
        predicted_target(*target, report_json["predicted_pose_error"], "calibrated");
  if (sensitivity) report_json["sensitivity"] = sensitivity_json(*sensitivity);
  CalibrationVerdict verdict = judge_calibration(report);
  if (target && report_json["target"]["meets"] == false)
    verdict.findings.push_back({"target", Finding::Level::kDoNotLoad,
                                "The calibration does not meet the target: " +
                                    report_json["target"]["verdict"].get<std::string>() + ".",
                                "Measure more, or better chosen, configurations (kincal design "
                                "--target), or state what you know as prior_std."});
  report_json["verdict"] = to_json(verdict);
  if (!report_to_stdout) {
    out() << to_text(report);
    out() << starts_text(starts_report);
    if (sensitivity) out() << sensitivity_text(*sensitivity);
    if (target) out() << "target: " << report_json["target"]["verdict"].get<std::string>() << "\n";
    out() << to_text(verdict);
  }
  // Model and report are written together or not at all while the process runs. Under a
  // crash between the two renames the report, renamed first, is new and the model old: the
  // report records the SHA-256 of the model written with it, and `kincal verify` tells.
  if (!null_directions.empty()) report_json["null_directions"] = null_directions;
  std::vector<std::pair<std::string, std::string>> outputs;
  std::string model_text;
  if (solved && vm.count("out")) {
    model_text = calibrated_model_text(vm["out"].as<std::string>(), *model,
                                       problem.full_parameters(x), fixed_by_identifiability);
    report_json["calibrated_model"] = {{"file", vm["out"].as<std::string>()},
                                       {"sha256", sha256_hex(model_text)}};
  } else {
    report_json["calibrated_model"] = nullptr;
  }
  if (!report_file.empty()) outputs.push_back({"--json", report_json.dump(2) + "\n"});
  if (vm.count("html")) outputs.push_back({"--html", render_calibration_html(report_json)});
  if (!model_text.empty()) outputs.push_back({"--out", model_text});
  plan.write(outputs);
  if (!solved) {
    err() << "kincal calibrate: error: the solver did not reach a solution ("
          << to_string(summary.termination) << ": " << summary.message
          << "); no calibrated model written\n";
    return 1;
  }
  if (summary.termination == TerminationType::kMaxIterations)
    note("calibrate", "iteration limit reached before convergence; consider --max-iterations");
  if (!vm.count("out") && !report_to_stdout)
    note("calibrate", "no --out given: the calibrated model was not saved");
  // Written, but not to be loaded: a distinct exit code, so that no script takes it for a
  // plain success.
  if (verdict.worst() == Finding::Level::kDoNotLoad) {
    for (const Finding& f : verdict.findings)
      if (f.level == Finding::Level::kDoNotLoad) {
        err() << "kincal calibrate: verdict: do not load this calibration: " << f.text << "\n";
        break;
      }
    return kDoNotLoadExitCode;
  }
  return 0;
}

}  // namespace kincal::cli
