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

namespace {

// Outside this range the information (spread / noise)^2 over- or underflows, or the figures
// mean nothing: 1e-9 mm is a picometre, 1e6 mm a kilometre.
constexpr double kNoiseStdMin = 1e-9, kNoiseStdMax = 1e6;

// "0.5" (no unit: `unit` stays "") or "0.5mm", "0.01rad", "0.5deg" (one value with its unit).
PriorStdRule parse_value(const std::string& text, bool bare_is_parameter_unit) {
  PriorStdRule rule;
  char* end = nullptr;
  const double bare = std::strtod(text.c_str(), &end);
  if (bare_is_parameter_unit && !text.empty() && end != text.c_str() && *end == '\0') {
    rule.value = bare;
  } else {
    const UnitValues values = UnitValues::parse(text);
    rule.unit = values.values().begin()->first;
    rule.value = values.values().begin()->second;
    if (values.values().size() != 1)
      throw std::invalid_argument("'" + text + "' gives more than one value");
  }
  // A subnormal or tiny std (1e-320) makes the prior's precision 1 / std^2 infinite: refused
  // here, naming the option, rather than found later as data that "determine only n of n".
  if (!(rule.value >= kMinPriorStd && rule.value <= kMaxPriorStd)) {
    char value[48] = "";
    if (!rule.unit.empty())  // converted (deg to rad): say what was compared
      std::snprintf(value, sizeof value, " (%g %s)", rule.value, rule.unit.c_str());
    throw std::invalid_argument("'" + text + "'" + value +
                                " is not a std between 1e-150 and 1e150");
  }
  return rule;
}

}  // namespace

std::vector<PriorStdRule> parse_prior_std(const std::string& spec) {
  std::vector<PriorStdRule> rules;
  std::string::size_type start = 0;
  while (true) {
    const auto comma = spec.find(',', start);
    const std::string item = spec.substr(start, comma - start);
    const auto eq = item.rfind('=');
    if (eq == 0) throw std::invalid_argument("'" + item + "' has no parameter pattern before '='");
    PriorStdRule rule =
        parse_value(eq == std::string::npos ? item : item.substr(eq + 1), eq != std::string::npos);
    if (eq != std::string::npos) rule.pattern = item.substr(0, eq);
    rules.push_back(rule);
    if (comma == std::string::npos) break;
    start = comma + 1;
  }
  return rules;
}

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

bool prior_std_per_unit_only(const std::vector<PriorStdRule>& rules) {
  for (const PriorStdRule& rule : rules)
    if (!rule.pattern.empty()) return false;
  return true;
}

void apply_prior_std(const po::variables_map& vm, MeasurementModel& model) {
  for (const PriorStdRule& rule : prior_std_rules(vm)) {
    if (rule.pattern.empty()) {
      // "*" reaches every parameter; a fixed one's prior is never used, so only free ones.
      model.parameters().for_each_matching("*", [&](Parameter& p) {
        if (p.free && p.unit == rule.unit) p.prior_std = rule.value;
      });
      continue;
    }
    try {
      model.parameters().for_each_matching(rule.pattern, [&](Parameter& p) {
        if (!rule.unit.empty() && rule.unit != p.unit)
          throw CliError("--prior-std: '" + rule.pattern + "' matches " + p.name + ", in " +
                         p.unit + ", but its std is in " + rule.unit);
        p.prior_std = rule.value;
      });
    } catch (const std::invalid_argument&) {
      throw CliError("--prior-std: '" + printable(rule.pattern) +
                     "' matches no parameter of the model");
    }
  }
}

bool check_prior_usable(const MeasurementModel& model, const std::string& model_file) {
  bool any = false;
  for (int i : model.parameters().free_indices()) any = any || model.parameters()[i].has_prior();
  if (any && !model.weighted())
    throw CliError(model_file +
                   ": a prior (prior_std, --prior-std) needs the readings' noise std to be "
                   "weighed against; give --noise-std (e.g. 0.0072mm) or \"reading_std\": "
                   "{\"<reading>\": std} in the model file (a / sqrt(3) for noise U[-a, a])");
  return any;
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
  const std::vector<std::string> units = model.reading_units();
  const UnitValues values = unit_values_option(vm, "noise-std");
  const std::string given = "--noise-std '" + printable(vm["noise-std"].as<std::string>()) + "'";
  VectorXd std(model.num_readings());
  for (int i = 0; i < model.num_readings(); ++i) {
    if (!values.has(units[i]))
      throw CliError(given + ": no value for " + units[i] + " (reading " +
                     model.reading_names()[i] + ")");
    std[i] = values.get(units[i]);
    if (!(std[i] >= kNoiseStdMin && std[i] <= kNoiseStdMax)) {
      char text[160];
      std::snprintf(text, sizeof text,
                    ": %g %s for reading %s; expected a noise std between %g and %g %s", std[i],
                    units[i].c_str(), model.reading_names()[i].c_str(), kNoiseStdMin, kNoiseStdMax,
                    units[i].c_str());
      throw CliError(given + text);
    }
  }
  return std;
}

void apply_noise_std(const po::variables_map& vm, MeasurementModel& model) {
  if (!vm.count("noise-std")) return;
  const VectorXd std = noise_std_per_reading(vm, model);
  const std::vector<std::string> names = model.reading_names();
  for (int i = 0; i < model.num_readings(); ++i) model.set_reading_std(names[i], std[i]);
}

}  // namespace kincal::cli
