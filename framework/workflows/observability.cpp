#include "kincal/framework/workflows/observability.hpp"

#include <cstdio>
#include <stdexcept>

#include "kincal/framework/analysis/calibration_report.hpp"
#include "kincal/framework/analysis/identifiability_check.hpp"
#include "kincal/framework/analysis/identifiability_words.hpp"
#include "kincal/framework/calibration/constrained_problem.hpp"
#include "kincal/framework/calibration/frame_turns.hpp"
#include "kincal/framework/calibration/prior_and_noise.hpp"
#include "kincal/framework/calibration/prior_problem.hpp"
#include "kincal/framework/calibration/simulation.hpp"

namespace kincal {

ObservabilityResult observe(const ObservabilityRequest& request) {
  const std::shared_ptr<const MeasurementModel>& model = request.model;
  if (!model) throw std::invalid_argument("observability: no model");
  ObservabilityResult result;
  result.model_file = request.model_file;
  result.source = request.source;
  result.with_prior =
      check_prior_usable(*model, request.model_file.empty() ? "the model" : request.model_file);
  const VectorXd values = model->parameters().nominal_values();
  const std::vector<int> free = model->parameters().free_indices();
  if (free.empty())
    throw std::invalid_argument("no free parameters: nothing to analyse (use --free)");
  result.num_free = static_cast<int>(free.size());
  result.configurations = request.data.size();

  const CalibrationProblem problem(model, request.data, values, free);
  VectorXd residuals;
  MatrixXd J;
  std::string why;
  if (!problem.evaluate(problem.initial_free_parameters(), &residuals, &J, &why))
    throw std::invalid_argument("cannot evaluate the identification Jacobian: " + why);
  // Only the readings present count, as in calibrate's report: a missing one is a zero row
  // that would count as a residual (and lower O1) without having been observed.
  const std::vector<int> present = problem.data().present_rows();
  J = J(present, Eigen::all).eval();
  residuals = residuals(present).eval();
  // Turns of the measurement frame that change no fit (sockets measured as 0), as calibrate
  // counts them: a gauge freedom the Jacobian does not show.
  MatrixXd turns = measurement_frame_turns(problem, problem.initial_free_parameters());
  if (turns.cols()) {
    std::vector<int> rows = present;
    for (Eigen::Index i = problem.data().readings.size(); i < turns.rows(); ++i)
      rows.push_back(static_cast<int>(i));
    turns = turns(rows, Eigen::all).eval();
  }
  // The model's parameter-only constraints (a known distance between fixtures) determine
  // what the readings may not, as they do in calibrate.
  append_constraint_rows(problem, problem.initial_free_parameters(), J, &residuals);
  const IdentifiabilityOptions& options = request.identifiability;
  Identifiability& a = result.identifiability;
  a = analyze_identifiability(J, problem.parameter_names(), options, turns);
  if (result.with_prior) {
    // Before measuring, the noise is as the model states it (sigma = 1 in whitened units).
    const VectorXd precision = model_prior(problem).precision();
    add_prior(a, J, precision, data_share(J, precision), options, turns);
  }
  // Where calibrate chooses the free set from the data (a mechanism with an identification
  // priority, no explicit mask): say here what it would keep and why it would fix the rest.
  if (a.rank_deficient() && !result.with_prior &&
      when_rank_deficient(*model, false, request.explicit_mask) ==
          WhenRankDeficient::kFixDependent) {
    const std::vector<int> keep = choose_identifiable(*model, free, J, options, turns);
    for (int k : keep)
      result.calibrate_keeps.push_back(problem.parameter_names()[static_cast<std::size_t>(k)]);
    for (const DependentParameter& d :
         dependent_parameters(J, problem.parameter_names(), keep, options, turns))
      result.null_directions.push_back(describe_dependent(d, *model));
  }
  return result;
}

Measurements random_configurations(const MeasurementModel& model, int count, std::uint64_t seed,
                                   const UnitValues& range) {
  if (count < 1) throw std::invalid_argument("the number of configurations must be at least 1");
  ScenarioOptions s;
  s.num_configurations = count;
  s.seed = seed;
  s.config_range = range;
  // Configurations the model's own values reach: no parameter errors, not even the
  // per-parameter ones of the model file.
  s.param_error_half_width = UnitValues();
  s.num_validation = 0;
  auto exact = std::make_shared<MeasurementModel>(model);
  exact->parameters().for_each_matching("*", [](Parameter& p) { p.error_half_width = 0; });
  return make_scenario(exact, s).calibration;
}

std::string observability_text(const ObservabilityResult& result) {
  const Identifiability& a = result.identifiability;
  std::string text = std::to_string(result.configurations) + " configurations\n" + to_text(a);
  if (result.with_prior) {
    text +=
        "determined by the data / by the prior (1 - posterior var / prior var, at the stated "
        "reading_std):\n";
    for (int i = 0; i < a.data_share.size(); ++i) {
      char line[160];
      std::snprintf(line, sizeof line, "  %-24s data %5.1f %%  prior %5.1f %%\n",
                    a.names[static_cast<std::size_t>(i)].c_str(), 100 * a.data_share[i],
                    100 * (1 - a.data_share[i]));
      text += line;
    }
  }
  if (a.num_residuals < a.num_parameters)
    text += "fewer readings (" + std::to_string(a.num_residuals) + ") than free parameters (" +
            std::to_string(a.num_parameters) + "): measure more configurations\n";
  if (!result.calibrate_keeps.empty()) {
    text += "an arm imported from a URDF: calibrate (without --free/--fix) keeps " +
            std::to_string(result.calibrate_keeps.size()) + " of the " +
            std::to_string(result.num_free) +
            " free parameters and fixes the others, each a duplicate of kept ones:\n";
    for (const auto& line : result.null_directions) text += "  " + line + "\n";
  }
  return text;
}

nlohmann::ordered_json observability_json(const ObservabilityResult& result,
                                          const nlohmann::ordered_json& extra) {
  nlohmann::ordered_json out = {{"format", "kincal-observability"}, {"version", 1}};
  out["model"] = result.model_file;
  out["source"] = result.source;
  out["configurations"] = result.configurations;
  out.update(to_json(result.identifiability));
  out.update(extra);
  if (!result.calibrate_keeps.empty()) {
    out["calibrate_keeps"] = result.calibrate_keeps;
    out["null_directions"] = result.null_directions;
  }
  return out;
}

}  // namespace kincal
