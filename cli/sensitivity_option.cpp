#include "kincal/cli/sensitivity_option.hpp"

#include <cstdio>
#include <stdexcept>

#include "kincal/cli/commands.hpp"
#include "kincal/cli/simulation_report.hpp"
#include "kincal/framework/kinematics/units.hpp"

namespace kincal::cli {

void add_sensitivity_options(po::options_description& options) {
  options.add_options()(
      "sensitivity", po::bool_switch(),
      "also: for each fixed parameter, the pose error an error in it leaves after calibrating "
      "the free ones (over the same configurations)")(
      "sensitivity-step", po::value<std::string>()->default_value("1mm,0.001rad"),
      "the error assumed in each fixed parameter, per unit");
}

std::optional<SensitivityResult> sensitivity_from_options(
    const po::variables_map& vm, const std::shared_ptr<const MeasurementModel>& model,
    const VectorXd& values, const Measurements& data, const std::vector<int>& free) {
  if (!vm.count("sensitivity") || !vm["sensitivity"].as<bool>()) return std::nullopt;
  const UnitValues step = unit_values_option(vm, "sensitivity-step");
  try {
    return fixed_parameter_sensitivity(model, values, data, data, free, step.get(kMillimetre, 1.0),
                                       step.get(kRadian, 1e-3));
  } catch (const std::runtime_error& e) {
    throw CliError(std::string("--sensitivity: ") + e.what());
  }
}

// The sensitivity table: what an error in each fixed parameter leaves after calibration.
std::string sensitivity_text(const SensitivityResult& s) {
  std::string out =
      "sensitivity to fixed parameters (each one off by the step below, the free ones "
      "re-calibrated; first order):\n";
  char buf[200];
  std::snprintf(buf, sizeof buf, "  %-22s %10s %14s %12s %12s %14s %14s\n", "parameter", "error",
                "residual RMS", "pos. mean", "pos. max", "orient. mean", "orient. max");
  out += buf;
  std::snprintf(buf, sizeof buf, "  %-22s %10s %14s %12s %12s %14s %14s\n", "", "", "(readings)",
                "(mm)", "(mm)", "(mrad)", "(mrad)");
  out += buf;
  for (const auto& r : s.rows) {
    char error[40];
    if (r.unit == kRadian)
      std::snprintf(error, sizeof error, "%g mrad", r.delta * 1000);
    else
      std::snprintf(error, sizeof error, "%g %s", r.delta, r.unit.c_str());
    std::snprintf(buf, sizeof buf, "  %-22s %10s %14.3g %12.4g %12.4g %14.4g %14.4g\n",
                  r.name.c_str(), error, r.residual_rms, r.position_mean, r.position_max,
                  r.orientation_mean * 1000, r.orientation_max * 1000);
    out += buf;
  }
  if (s.free_rank < s.num_free)
    out += "  (the free parameters are rank deficient: " + std::to_string(s.free_rank) + " of " +
           std::to_string(s.num_free) +
           " determined; the re-calibration takes the smallest correction)\n";
  return out;
}

}  // namespace kincal::cli
