#pragma once
// The options several commands share in meaning, defined and parsed once, so that each is
// spelled, written and checked the same everywhere (tests/cli/option_vocabulary_test.cpp walks
// every command's --help to hold them to it):
//
//   --prior-std SPEC   Gaussian priors, per unit (2.887mm,0.0058rad) or per pattern
//                      ('leg*.base.z=0.5mm'), or both, repeatable: calibrate, design,
//                      observability, simulate
//   --noise-std SPEC   the readings' noise as a standard deviation per unit (0.0007mm):
//                      calibrate, validate, observability, design, simulate
//   --threads N        worker threads, 0 = all cores: calibrate, simulate, reproduce

#include <string>
#include <vector>

#include "kincal/cli/cli_util.hpp"
#include "kincal/framework/calibration/prior_and_noise.hpp"
#include "kincal/framework/kinematics/measurement_model.hpp"

namespace kincal::cli {

/// Adds --prior-std SPEC (repeatable; later items win).
void add_prior_std_option(po::options_description& options);
/// Every --prior-std item in order, parsed; a malformed one is a CliError naming it.
std::vector<PriorStdRule> prior_std_rules(const po::variables_map& vm);
/// Sets the prior std of the parameters each rule names, replacing the model file's; a
/// pattern matching nothing or a value in another unit than its parameter's is a CliError.
void apply_prior_std(const po::variables_map& vm, MeasurementModel& model);

/// Adds --config-range SPEC: the half-width per unit of the box around the home actuator
/// values from which configurations are drawn (simulate, reproduce, observability, design).
void add_config_range_option(po::options_description& options);

/// Adds --allow-rank-deficient: fix what the data cannot determine instead of stopping
/// (calibrate, simulate; framework/analysis/identifiability_check.hpp).
void add_allow_rank_deficient_option(po::options_description& options);

/// Adds --threads N (default 0 = all cores): the worker threads that evaluate the residuals
/// (calibrate, simulate: split only when each thread gets 256 configurations or more) or that
/// run the trials (reproduce). kincal's own solvers give the same result for every N.
void add_threads_option(po::options_description& options);
/// --threads, checked (0 to 1024), with 0 as the number of cores.
int threads_option(const po::variables_map& vm);

/// Adds --noise-std SPEC: `meaning` says what the std does in this command (e.g. "replaces
/// the model's reading_std"), after the shared text.
void add_noise_std_option(po::options_description& options, const std::string& meaning);
/// The noise std of each reading from --noise-std (every reading unit needs a value), or the
/// model's reading_std when it is not given. Values outside [1e-9, 1e6] are a CliError.
VectorXd noise_std_per_reading(const po::variables_map& vm, const MeasurementModel& model);
/// Sets the model's reading_std from --noise-std, when given.
void apply_noise_std(const po::variables_map& vm, MeasurementModel& model);

}  // namespace kincal::cli
