#include "kincal/cli/shared_options.hpp"

#include <cmath>
#include <cstdio>
#include <cstdlib>
#include <stdexcept>

#include "kincal/cli/simulation_report.hpp"
#include "kincal/framework/base/message_excerpt.hpp"
#include "kincal/framework/base/parallel.hpp"
#include "kincal/framework/kinematics/units.hpp"

namespace kincal::cli {

void add_prior_std_option(po::options_description& options) {
  options.add_options()(
      "prior-std", po::value<std::vector<std::string>>()->composing(),
      "Gaussian prior around the model's values, replacing the model file's prior_std: per "
      "unit on every free parameter (2.887mm,0.0058rad; a bare number is mm) or per pattern "
      "('leg*.base.z=0.5mm'; without a unit, the parameter's), comma-separated, repeatable, "
      "later items win");
}

std::vector<PriorStdRule> prior_std_rules(const po::variables_map& vm) {
  std::vector<PriorStdRule> rules;
  if (!vm.count("prior-std")) return rules;
  for (const auto& entry : vm["prior-std"].as<std::vector<std::string>>()) {
    try {
      for (const PriorStdRule& rule : parse_prior_std(entry)) rules.push_back(rule);
    } catch (const std::invalid_argument& e) {
      throw CliError("--prior-std '" + printable(entry) + "': " + e.what() +
                     "; expected e.g. 2.887mm,0.0058rad or 'leg*.base.z=0.5mm'");
    }
  }
  return rules;
}

void apply_prior_std(const po::variables_map& vm, MeasurementModel& model) {
  try {
    kincal::apply_prior_std(prior_std_rules(vm), model);
  } catch (const std::invalid_argument& e) {
    throw CliError(std::string("--prior-std: ") + e.what());
  }
}

void add_config_range_option(po::options_description& options) {
  options.add_options()("config-range", po::value<std::string>(),
                        "half-width of the box around the home actuator values from which "
                        "configurations are drawn, per unit, e.g. 20mm,0.5rad (default: each "
                        "actuator's range in the model)");
}

void add_allow_rank_deficient_option(po::options_description& options) {
  options.add_options()("allow-rank-deficient", po::bool_switch(),
                        "when the data cannot determine every free parameter, fix the dependent "
                        "ones at their model values and solve for the rest instead of stopping "
                        "(what an arm imported from a URDF does by default, without "
                        "--free/--fix)");
}

void add_threads_option(po::options_description& options) {
  options.add_options()("threads", po::value<int>()->default_value(0),
                        "worker threads (0 = all cores)");
}

int threads_option(const po::variables_map& vm) {
  const int threads = vm["threads"].as<int>();
  if (threads < 0 || threads > 1024) throw CliError("--threads must be from 0 to 1024");
  return threads == 0 ? hardware_threads() : threads;
}

void add_noise_std_option(po::options_description& options, const std::string& meaning) {
  options.add_options()("noise-std", po::value<std::string>(),
                        ("the readings' noise standard deviation per unit, e.g. 0.0007mm or "
                         "0.05mm,1e-4rad (a bare number is mm): " +
                         meaning)
                            .c_str());
}

VectorXd noise_std_per_reading(const po::variables_map& vm, const MeasurementModel& model) {
  if (!vm.count("noise-std")) return model.reading_std();
  const UnitValues values = unit_values_option(vm, "noise-std");
  try {
    return kincal::noise_std_per_reading(values, model);
  } catch (const std::invalid_argument& e) {
    throw CliError("--noise-std '" + printable(vm["noise-std"].as<std::string>()) +
                   "': " + e.what());
  }
}

void apply_noise_std(const po::variables_map& vm, MeasurementModel& model) {
  if (!vm.count("noise-std")) return;
  const VectorXd std = noise_std_per_reading(vm, model);
  const std::vector<std::string> names = model.reading_names();
  for (int i = 0; i < model.num_readings(); ++i) model.set_reading_std(names[i], std[i]);
}

}  // namespace kincal::cli
