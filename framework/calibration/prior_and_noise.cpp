#include "kincal/framework/calibration/prior_and_noise.hpp"

#include <cstdio>
#include <cstdlib>
#include <stdexcept>

#include "kincal/framework/base/message_excerpt.hpp"

namespace kincal {

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
  // here, naming the item, rather than found later as data that "determine only n of n".
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

bool prior_std_per_unit_only(const std::vector<PriorStdRule>& rules) {
  for (const PriorStdRule& rule : rules)
    if (!rule.pattern.empty()) return false;
  return true;
}

void apply_prior_std(const std::vector<PriorStdRule>& rules, MeasurementModel& model) {
  for (const PriorStdRule& rule : rules) {
    if (rule.pattern.empty()) {
      // "*" reaches every parameter; a fixed one's prior is never used, so only free ones.
      model.parameters().for_each_matching("*", [&](Parameter& p) {
        if (p.free && p.unit == rule.unit) p.prior_std = rule.value;
      });
      continue;
    }
    // The unit mismatch is found inside the walk; it must not read as "matches nothing".
    std::string mismatch;
    try {
      model.parameters().for_each_matching(rule.pattern, [&](Parameter& p) {
        if (!rule.unit.empty() && rule.unit != p.unit) {
          if (mismatch.empty())
            mismatch = "'" + rule.pattern + "' matches " + p.name + ", in " + p.unit +
                       ", but its std is in " + rule.unit;
          return;
        }
        p.prior_std = rule.value;
      });
    } catch (const std::invalid_argument&) {
      throw std::invalid_argument("'" + printable(rule.pattern) +
                                  "' matches no parameter of the model");
    }
    if (!mismatch.empty()) throw std::invalid_argument(mismatch);
  }
}

bool check_prior_usable(const MeasurementModel& model, const std::string& model_file) {
  bool any = false;
  for (int i : model.parameters().free_indices()) any = any || model.parameters()[i].has_prior();
  if (any && !model.weighted())
    throw std::invalid_argument(
        model_file +
        ": a prior (prior_std, --prior-std) needs the readings' noise std to be weighed "
        "against; give --noise-std (e.g. 0.0072mm) or \"reading_std\": {\"<reading>\": std} in "
        "the model file (a / sqrt(3) for noise U[-a, a])");
  return any;
}

VectorXd noise_std_per_reading(const UnitValues& noise, const MeasurementModel& model) {
  const std::vector<std::string> units = model.reading_units();
  VectorXd std(model.num_readings());
  for (int i = 0; i < model.num_readings(); ++i) {
    if (!noise.has(units[i]))
      throw std::invalid_argument("no value for " + units[i] + " (reading " +
                                  model.reading_names()[i] + ")");
    std[i] = noise.get(units[i]);
    if (!(std[i] >= kNoiseStdMin && std[i] <= kNoiseStdMax)) {
      char text[160];
      std::snprintf(text, sizeof text,
                    "%g %s for reading %s; expected a noise std between %g and %g %s", std[i],
                    units[i].c_str(), model.reading_names()[i].c_str(), kNoiseStdMin, kNoiseStdMax,
                    units[i].c_str());
      throw std::invalid_argument(text);
    }
  }
  return std;
}

UnitValues parse_non_negative_unit_values(const std::string& text) {
  const UnitValues values = UnitValues::parse(text);
  for (const auto& [unit, value] : values.values())
    if (!(value >= 0)) throw std::invalid_argument("expected values >= 0");
  return values;
}

}  // namespace kincal
