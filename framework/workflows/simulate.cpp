#include "kincal/framework/workflows/simulate.hpp"

#include <cmath>
#include <cstdio>
#include <cstdlib>
#include <stdexcept>

#include "kincal/framework/analysis/identifiability_check.hpp"
#include "kincal/framework/analysis/identifiability_words.hpp"
#include "kincal/framework/base/message_excerpt.hpp"
#include "kincal/framework/calibration/prior_and_noise.hpp"
#include "kincal/framework/kinematics/units.hpp"
#include "kincal/framework/least_squares/solver_registry.hpp"
#include "kincal/framework/workflows/option_name.hpp"

namespace kincal {

namespace {

std::string option(const std::string& prefix, const std::string& name) {
  return option_name(prefix, name);
}
std::string option(const SimulateRequest& request, const std::string& name) {
  return option(request.option_prefix, name);
}

// Values per unit, each >= 0; the error names the option and the text.
UnitValues unit_values(const std::string& prefix, const std::string& name,
                       const std::string& text) {
  try {
    return parse_non_negative_unit_values(text);
  } catch (const std::invalid_argument& e) {
    throw std::invalid_argument(option(prefix, name) + " '" + text + "': " + e.what());
  }
}

// Each free parameter's unit needs a std when the prior is given per unit.
void check_prior_per_unit(const SimulateRequest& request) {
  const ScenarioOptions& o = request.scenario;
  if (!o.prior_std.any_positive()) return;
  const MeasurementModel& model = *request.model;
  for (int i : model.parameters().free_indices()) {
    const Parameter& p = model.parameters()[i];
    if (!(o.prior_std_for(p.unit) > 0))
      throw std::invalid_argument(
          option(request, "prior-std") + " gives no std in " + p.unit + " for free parameter " +
          p.name +
          "; expected one per unit of the free parameters, e.g. 2.887mm,0.0058rad, or per "
          "pattern, e.g. '*.z=0.5mm'");
  }
}

// The scenario options with the configurations chosen by experiment design on the nominal
// model (the truth is unknown when a design is made), for the same count, noise and box.
ScenarioOptions designed_options(const SimulateRequest& request, std::string* text) {
  const MeasurementModel& model = *request.model;
  const ScenarioOptions& base = request.scenario;
  DesignOptions d;
  d.criterion = *request.design;
  d.count = base.num_configurations;
  d.num_random = request.design_candidates;
  if (d.num_random < 0)
    throw std::invalid_argument(option(request, "design-candidates") + " must be >= 0");
  d.seed = base.seed;
  d.default_error_mm = base.param_error_for(kMillimetre);
  d.default_error_rad = base.param_error_for(kRadian);
  MeasurementModel designed = model;
  const auto units = model.reading_units();
  d.noise_std = model.reading_std();
  for (int i = 0; i < model.num_readings(); ++i) {
    const double a = base.noise_for(units[i]);
    if (a > 0) d.noise_std[i] = a / std::sqrt(3.0);  // uniform U[-a, a]
  }
  // The prior the calibration will use (ScenarioOptions::prior_std replaces the model's).
  if (base.prior_std.any_positive())
    designed.parameters().for_each_matching("*", [&](Parameter& p) {
      if (p.free) p.prior_std = base.prior_std_for(p.unit);
    });
  for (const Actuator& a : model.mechanism().actuators()) {
    const double r = base.config_range_for(a.unit);
    if (!std::isnan(r)) designed.set_actuator_range(a.name, r);
  }
  const DesignRun run = run_design(designed, d);
  ScenarioOptions out = base;
  out.planned = run.rows;
  out.num_configurations = run.rows.size();
  char buf[200];
  std::snprintf(buf, sizeof buf,
                "configurations chosen by design: criterion %s, %d measurements from %d "
                "candidates, seed %llu",
                to_string(d.criterion), d.count, run.candidates.size(),
                static_cast<unsigned long long>(d.seed));
  *text = buf;
  return out;
}

}  // namespace

ScenarioOptions scenario_options(const ScenarioText& text, const std::string& prefix) {
  ScenarioOptions s;
  if (text.case_id != 0) {
    if (text.poses || text.noise_half_width)
      throw std::invalid_argument(option(prefix, "case") + " sets " + option(prefix, "poses") +
                                  " and " + option(prefix, "noise-half-width") + "; give either " +
                                  option(prefix, "case") + " or those two");
    try {
      const PaperCase& c = paper_case(text.case_id);
      s.num_configurations = c.num_configurations;
      s.noise_half_width.set(kMillimetre, c.noise_half_width);
    } catch (const std::invalid_argument& e) {
      throw std::invalid_argument(option(prefix, "case") + ": " + e.what());
    }
  }
  if (text.poses) s.num_configurations = *text.poses;
  if (text.noise_half_width) {
    s.noise_half_width = unit_values(prefix, "noise-half-width", *text.noise_half_width);
  }
  const UnitValues error = unit_values(prefix, "param-error", text.param_error);
  // "0" is the truth itself: zero in every unit, not only in the bare number's (mm), which
  // left the angles drawn at ±0.01 rad.
  char* end = nullptr;
  const bool bare_zero = std::strtod(text.param_error.c_str(), &end) == 0 &&
                         end != text.param_error.c_str() && *end == '\0';
  s.param_error_half_width = bare_zero ? UnitValues() : error.over(s.param_error_half_width);
  if (text.config_range) {
    s.config_range = unit_values(prefix, "config-range", *text.config_range);
  }
  s.seed = text.seed;
  s.num_validation = text.validation;
  if (s.num_configurations < 1)
    throw std::invalid_argument(option(prefix, "poses") + " must be at least 1");
  if (s.num_validation < 1)
    throw std::invalid_argument(option(prefix, "validation") + " must be at least 1");
  if (text.noise_std) {
    if (text.noise_half_width || text.case_id != 0)
      throw std::invalid_argument(option(prefix, "noise-std") + " is the noise's std, " +
                                  option(prefix, "noise-half-width") + " its half-width, " +
                                  option(prefix, "case") + " sets it: give one of them");
    s.noise_half_width = unit_values(prefix, "noise-std", *text.noise_std).scaled(std::sqrt(3.0));
  }
  return s;
}

Measurements planned_rows(Measurements rows) {
  for (int r = 0; r < rows.size(); ++r)
    if (rows.readings.row(r).array().isNaN().all()) rows.readings.row(r).setZero();
  return rows;
}

SimulateResult simulate(const SimulateRequest& request) {
  if (!request.model) throw std::invalid_argument("simulate: the request has no model");
  const std::shared_ptr<const MeasurementModel>& model = request.model;
  SimulateResult result;
  result.model_name = request.model_name;
  result.configs_file = request.configs_file;
  result.truth_file = request.truth_file;
  result.case_id = request.case_id;
  const auto say = [&](const std::string& text) {
    result.notes.push_back(text);
    if (request.on_note) request.on_note(text);
  };
  check_prior_per_unit(request);
  std::shared_ptr<const Solver> solver =
      request.solver ? request.solver : SolverRegistry::global().create("lm");

  ScenarioOptions run_options = request.scenario;
  if (request.design) run_options = designed_options(request, &result.design_text);
  Scenario& scenario = result.scenario;
  try {
    scenario = make_scenario(model, run_options);
  } catch (const std::invalid_argument& e) {
    if (!request.priors_given) throw;
    throw std::invalid_argument(option(request, "prior-std") + ": " + e.what());
  } catch (const std::runtime_error& e) {
    if (request.configs_file.empty()) throw;
    throw std::invalid_argument(option(request, "configs") + " " + printable(request.configs_file) +
                                ": " + e.what());
  }
  // As in calibrate: fewer readings than unknowns cannot determine them (the paper needs
  // m > n), and a solver would report a perfect fit of a wrong geometry.
  const long long readings =
      static_cast<long long>(scenario.calibration.size()) * scenario.model->num_readings();
  const int unknowns = static_cast<int>(scenario.free_indices.size());
  if (readings < unknowns)
    throw std::invalid_argument(
        (!request.configs_file.empty()
             ? option(request, "configs") + " " + printable(request.configs_file) + " (" +
                   std::to_string(scenario.calibration.size()) + " configurations)"
             : option(request, "poses") + " " + std::to_string(scenario.calibration.size())) +
        ": " + std::to_string(readings) + " readings cannot determine " + std::to_string(unknowns) +
        " free parameters (need at least " +
        std::to_string((unknowns + scenario.model->num_readings() - 1) /
                       scenario.model->num_readings()) +
        " configurations; see kincal observability)");
  // The same identifiability check as calibrate's, on the simulated data at the nominal
  // values: calibrate refuses data that cannot determine the free parameters, and a solve of
  // them would end "converged" somewhere in a valley of equally good fits.
  {
    const std::shared_ptr<CalibrationProblem> problem = scenario.make_problem();
    VectorXd r;
    MatrixXd J;
    if (problem->evaluate(problem->initial_free_parameters(), &r, &J)) {
      const IdentifiabilityCheck check = check_identifiability(
          "the simulated data (" + std::to_string(scenario.calibration.size()) +
              " configurations, seed " + std::to_string(scenario.options.seed) + ")",
          *problem, J, when_rank_deficient(*model, request.allow_rank_deficient, false),
          IdentifiabilityOptions{}, request.rank_deficiency_remedy);
      for (const std::string& text : check.notes) say(text);
      if (!check.fixed.empty()) {
        const std::string table = fixed_parameters_table(check.fixed, check.fixed_effects);
        for (std::size_t start = 0, end; start < table.size(); start = end + 1) {
          end = table.find('\n', start);
          say(table.substr(start, end - start));
        }
      }
      scenario.free_indices = check.free;
      result.fixed_by_identifiability = check.fixed;
    }
  }
  // Several starts: the best is solved again with the per-iteration validation errors.
  const Formulation formulation =
      request.formulation ? *request.formulation : default_formulation(*scenario.model);
  const SolverOptions& options = request.solver_options;
  CalibrationRun& run = result.run;
  if (request.starts > 1) {
    if (formulation == Formulation::kImplicit)
      say(option(request, "starts") +
          " solves the nested formulation; the best start is solved again in the implicit one");
    result.starts.result =
        solve_scenario_starts(scenario, *solver, options, request.starts, options.num_threads);
    result.starts.seed = scenario.options.seed;
    result.starts.spread_from = "the simulated parameter errors";
    const MultiStartResult& starts = result.starts.result;
    const StartOutcome& best = starts.starts[starts.best_start];
    if (starts.stopped) {
      // Stopped (Ctrl-C): the estimate is where the best start got to. Its solve from there
      // stops at once, the stop being still asked for; the summary is the starts' own.
      run = run_calibration(scenario, *solver, options, true, formulation, best.x);
      run.summary = starts.estimate_summary();
    } else {
      run = run_calibration(scenario, *solver, options, true, formulation, best.start);
    }
  } else {
    run = run_calibration(scenario, *solver, options, true, formulation);
    const auto problem = scenario.make_problem();
    VectorXd x(scenario.free_indices.size());
    for (int i = 0; i < x.size(); ++i) x[i] = run.estimate[scenario.free_indices[i]];
    result.starts = single_start_report(problem->initial_free_parameters(), x, run.summary,
                                        scenario.options.seed);
  }
  if (!run.formulation_note.empty()) say(run.formulation_note);
  result.solved =
      run.summary.converged() || run.summary.termination == TerminationType::kMaxIterations;
  return result;
}

}  // namespace kincal
