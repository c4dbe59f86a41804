#pragma once
// --sensitivity and --sensitivity-step, shared by observability (before measuring) and
// calibrate (on the data calibrated from, whose report page then has its "Sensitivity to
// fixed parameters" section): for each fixed parameter, the pose error an error in it leaves
// after calibrating the free ones (framework/analysis/fixed_parameter_sensitivity.hpp).

#include <memory>
#include <optional>
#include <string>
#include <vector>

#include "kincal/cli/cli_util.hpp"
#include "kincal/framework/analysis/fixed_parameter_sensitivity.hpp"

namespace kincal::cli {

/// Adds --sensitivity and --sensitivity-step.
void add_sensitivity_options(po::options_description& options);

/// The analysis when --sensitivity is given (else nullopt), over the configurations of
/// `data` at `values` (full parameter vector). Throws CliError "--sensitivity: ..." when the
/// model cannot be evaluated there or --sensitivity-step is not a value per unit.
std::optional<SensitivityResult> sensitivity_from_options(
    const po::variables_map& vm, const std::shared_ptr<const MeasurementModel>& model,
    const VectorXd& values, const Measurements& data, const std::vector<int>& free);

/// The table for the terminal.
std::string sensitivity_text(const SensitivityResult& s);

}  // namespace kincal::cli
