#include "kincal/framework/calibration/simulation.hpp"

#include <algorithm>
#include <chrono>
#include <cmath>
#include <limits>
#include <map>
#include <set>
#include <stdexcept>

#include "kincal/framework/base/parallel.hpp"
#include "kincal/framework/base/random.hpp"
#include "kincal/framework/base/statistics.hpp"
#include "kincal/framework/calibration/constrained_problem.hpp"
#include "kincal/framework/calibration/prior_problem.hpp"
#include "kincal/framework/kinematics/units.hpp"

namespace kincal {

const std::vector<PaperCase>& paper_cases() {
  static const std::vector<PaperCase> cases = {
      {1, 0.0, 30}, {2, 0.00125, 30}, {3, 0.00125, 40}, {4, 0.0125, 40}, {5, 0.0125, 60}};
  return cases;
}

const PaperCase& paper_case(int id) {
  for (const auto& c : paper_cases())
    if (c.id == id) return c;
  throw std::invalid_argument("no case " + std::to_string(id) +
                              " in the paper's Table 2 (cases are 1 to 5)");
}

double ScenarioOptions::param_error_for(const std::string& unit) const {
  return param_error_half_width.get(unit, 0);
}

double ScenarioOptions::noise_for(const std::string& unit) const {
  return noise_half_width.get(unit, 0);
}

double ScenarioOptions::config_range_for(const std::string& unit) const {
  return config_range.get(unit, std::numeric_limits<double>::quiet_NaN());
}

double ScenarioOptions::prior_std_for(const std::string& unit) const {
  return prior_std.get(unit, 0);
}

std::shared_ptr<CalibrationProblem> Scenario::make_problem() const {
  return std::make_shared<CalibrationProblem>(model, calibration, nominal, free_indices);
}

namespace {

enum Stream : std::uint64_t {
  kTruthStream = 1,
  kConfigStream = 2,
  kNoiseStream = 3,
  kValidationStream = 4
};

// Draws `count` configurations in the box home_q +- range that the true geometry can
// reach; fills their true poses.
// Candidates drawn at a time. A draw that forward kinematics rejects is replaced by the next
// one, so the candidates are drawn in order from `rng` and accepted in that order; only
// their forward kinematics runs in parallel, and the configurations are those of a one-by-one
// loop whatever the threads (10^6 of them took 1.4 s on one core).
constexpr int kCandidatesPerBatch = 4096;

void draw_configurations(const MeasurementModel& model, const VectorXd& truth,
                         const VectorXd& home_q, const VectorXd& range, int count, Random& rng,
                         MatrixXd& actuators, std::vector<Pose>& poses) {
  const Mechanism& mechanism = model.mechanism();
  const auto mech_truth = truth.head(mechanism.num_parameters());
  const int na = mechanism.num_actuators();
  actuators.resize(count, na);
  poses.assign(count, Pose{});
  // 64 bits: 1000 attempts per configuration overflow an int beyond 2.1 million of them.
  const long long max_attempts = 1000LL * std::max(count, 1);
  long long attempts = 0;
  const int batch = std::min(count, kCandidatesPerBatch);
  MatrixXd candidates(batch, na);
  std::vector<ForwardKinematicsResult> reached(static_cast<std::size_t>(batch));
  auto reach = [&](int begin, int end) {
    for (int c = begin; c < end; ++c)
      reached[static_cast<std::size_t>(c)] =
          mechanism.forward_kinematics(mech_truth, candidates.row(c).transpose(),
                                       mechanism.home_pose(), model.forward_kinematics_options());
  };
  // Threads only from two batches on: below, they cost more than they save (and
  // reproduce's trials already run in parallel). Work is handed out in chunks of 256.
  const bool threaded = count >= 2 * kCandidatesPerBatch;
  constexpr int kChunk = 256;
  // Where sensors can miss (a camera), a drawn configuration must give at least one reading,
  // as an experiment keeps only the configurations in which something was measured (a camera
  // that sees its target); the readings a sensor misses there stay missing.
  const bool check_sensors = model.sensors_can_miss();
  VectorXd readings(check_sensors ? model.num_readings() : 0);
  long long unseen = 0;
  for (int j = 0; j < count;) {
    for (int c = 0; c < batch; ++c)
      for (int i = 0; i < na; ++i) candidates(c, i) = home_q[i] + rng.symmetric(range[i]);
    if (threaded)
      parallel_for((batch + kChunk - 1) / kChunk, 0, [&](int chunk) {
        reach(chunk * kChunk, std::min(batch, (chunk + 1) * kChunk));
      });
    else
      reach(0, batch);
    for (int c = 0; c < batch && j < count; ++c) {
      if (++attempts > max_attempts)
        throw std::runtime_error(
            unseen * 2 > attempts
                ? "could not draw configurations in which a sensor takes a reading (a "
                  "camera: its target in view); is the configuration range too large, or the "
                  "sensor placed where it sees nothing?"
                : "could not draw reachable configurations: forward kinematics of the true "
                  "model keeps failing (is the configuration range too large?)");
      const ForwardKinematicsResult& fk = reached[static_cast<std::size_t>(c)];
      if (!fk.ok()) continue;
      if (check_sensors &&
          model.simulate_at_pose(truth, fk.pose, readings) == model.num_readings()) {
        ++unseen;
        continue;
      }
      actuators.row(j) = candidates.row(c);
      poses[j] = fk.pose;
      ++j;
    }
  }
}

}  // namespace

Scenario make_scenario(std::shared_ptr<const MeasurementModel> model,
                       const ScenarioOptions& options) {
  if (options.num_configurations < 1)
    throw std::invalid_argument("the number of configurations must be at least 1");
  const auto non_negative = [](const UnitValues& values, bool nan_is_unset) {
    for (const auto& [unit, v] : values.values())
      if (!((v >= 0 && std::isfinite(v)) || (nan_is_unset && std::isnan(v)))) return false;
    return true;
  };
  if (!non_negative(options.noise_half_width, false) ||
      !non_negative(options.param_error_half_width, false) ||
      !non_negative(options.config_range, true) || !non_negative(options.prior_std, false) ||
      options.num_validation < 0)
    throw std::invalid_argument(
        "noise, parameter error, range, prior std and validation size must be finite and >= 0");
  Scenario s;
  if (options.prior_std.any_positive()) {
    auto with_prior = std::make_shared<MeasurementModel>(*model);
    // Every free parameter: "*" reaches them all, and a fixed one's prior is never used.
    with_prior->parameters().for_each_matching("*", [&](Parameter& p) {
      if (p.free) p.prior_std = options.prior_std_for(p.unit);
    });
    model = with_prior;
  }
  bool has_prior = false;
  for (int i : model->parameters().free_indices())
    has_prior = has_prior || model->parameters()[i].has_prior();
  s.model = model;
  // Readings in mm and rad weighed 1:1 would let one unit drown the other: when the model
  // states no reading std, a simulation that knows its noise weighs by it (uniform noise
  // U[-a, a] has std a / sqrt(3)). With a single unit the weight is a constant factor that
  // changes nothing but the cost's scale, so it is left alone.
  const std::vector<std::string> reading_units = model->reading_units();
  std::set<std::string> distinct_units(reading_units.begin(), reading_units.end());
  bool every_unit_has_noise = true;
  for (const std::string& unit : distinct_units)
    every_unit_has_noise = every_unit_has_noise && options.noise_for(unit) > 0;
  const bool mixed_units = distinct_units.size() > 1;
  if (has_prior && !model->weighted()) {
    // The prior's std is absolute; the data residuals must be in units of their noise std too.
    auto weighted = std::make_shared<MeasurementModel>(*model);
    const auto names = model->reading_names();
    for (std::size_t i = 0; i < names.size(); ++i) {
      const double a = options.noise_for(reading_units[i]);
      if (!(a > 0))
        throw std::invalid_argument(
            "a prior needs the readings' noise std: give the simulation reading noise > 0 (" +
            std::string(reading_units[i]) + ") or state reading_std in the model file");
      weighted->set_reading_std(names[i], a / std::sqrt(3.0));
    }
    s.model = weighted;
  } else if (mixed_units && !model->weighted() && every_unit_has_noise) {
    auto weighted = std::make_shared<MeasurementModel>(*model);
    const auto names = model->reading_names();
    for (std::size_t i = 0; i < names.size(); ++i)
      weighted->set_reading_std(names[i], options.noise_for(reading_units[i]) / std::sqrt(3.0));
    s.model = weighted;
  }
  s.options = options;
  s.nominal = model->parameters().nominal_values();
  s.free_indices = model->parameters().free_indices();

  Random truth_rng(derive_seed(options.seed, kTruthStream));
  s.truth = s.nominal;
  if (options.truth.size() > 0) {
    if (options.truth.size() != s.nominal.size() || !options.truth.allFinite())
      throw std::invalid_argument("the true parameter values do not fit the model (" +
                                  std::to_string(options.truth.size()) + " values for " +
                                  std::to_string(s.nominal.size()) + " parameters)");
    s.truth = options.truth;
  } else {
    for (int i : s.free_indices) {
      const Parameter& p = model->parameters()[i];
      const double e =
          std::isnan(p.error_half_width) ? options.param_error_for(p.unit) : p.error_half_width;
      s.truth[i] += truth_rng.symmetric(e);
    }
  }

  // Commanded actuator values at home come from the nominal model, as a controller would.
  const Mechanism& mechanism = model->mechanism();
  s.home_actuators.resize(mechanism.num_actuators());
  const InverseKinematicsResult home =
      mechanism.home_actuators(s.nominal.head(mechanism.num_parameters()), s.home_actuators);
  if (!home.ok())
    throw std::invalid_argument("the model's home pose is not reachable: inverse kinematics " +
                                home.describe());
  s.actuator_ranges = model->actuator_ranges();
  for (int i = 0; i < mechanism.num_actuators(); ++i) {
    const double r = options.config_range_for(mechanism.actuators()[i].unit);
    if (!std::isnan(r)) s.actuator_ranges[i] = r;
  }

  Random config_rng(derive_seed(options.seed, kConfigStream));
  std::vector<Pose> calibration_poses;
  const bool planned = options.planned.size() > 0;
  if (planned) {
    const auto mismatch = [](const std::string& what, long long planned, long long expected) {
      return std::invalid_argument("the planned configurations have " + std::to_string(planned) +
                                   " " + what + ", expected " + std::to_string(expected));
    };
    if (options.planned.size() != options.num_configurations)
      throw mismatch("rows", options.planned.size(), options.num_configurations);
    if (options.planned.actuators.cols() != mechanism.num_actuators())
      throw mismatch("actuator columns", options.planned.actuators.cols(),
                     mechanism.num_actuators());
    if (options.planned.readings.cols() != model->num_readings())
      throw mismatch("reading columns", options.planned.readings.cols(), model->num_readings());
    s.calibration.actuators = options.planned.actuators;
    for (int j = 0; j < options.planned.size(); ++j) {
      const ForwardKinematicsResult fk = mechanism.forward_kinematics(
          s.truth.head(mechanism.num_parameters()), options.planned.actuators.row(j).transpose(),
          mechanism.home_pose(), model->forward_kinematics_options());
      if (!fk.ok())
        throw std::runtime_error("planned configuration " + std::to_string(j + 1) +
                                 " is not reachable with the true parameters: " + fk.describe());
      calibration_poses.push_back(fk.pose);
    }
  } else {
    draw_configurations(*model, s.truth, s.home_actuators, s.actuator_ranges,
                        options.num_configurations, config_rng, s.calibration.actuators,
                        calibration_poses);
  }

  Random noise_rng(derive_seed(options.seed, kNoiseStream));
  const int k = model->num_readings();
  const std::vector<std::string> units = model->reading_units();
  s.calibration.readings.resize(options.num_configurations, k);
  VectorXd reading(k), noise(k);
  for (int j = 0; j < options.num_configurations; ++j) {
    model->simulate_at_pose(s.truth, calibration_poses[j], reading);
    for (int i = 0; i < k; ++i) noise[i] = noise_rng.symmetric(options.noise_for(units[i]));
    model->retract(reading, noise);
    if (planned)  // readings the plan does not take stay missing
      for (int i = 0; i < k; ++i)
        if (std::isnan(options.planned.readings(j, i))) reading[i] = NAN;
    s.calibration.readings.row(j) = reading.transpose();
  }

  Random validation_rng(derive_seed(options.seed, kValidationStream));
  draw_configurations(*model, s.truth, s.home_actuators, s.actuator_ranges, options.num_validation,
                      validation_rng, s.validation_actuators, s.validation_poses);
  return s;
}

PoseErrorStats validation_errors(const Scenario& scenario, const VectorXd& params) {
  PoseErrorStats stats;
  const Mechanism& mechanism = scenario.model->mechanism();
  const auto mech_params = params.head(mechanism.num_parameters());
  const int count = static_cast<int>(scenario.validation_poses.size());
  int ok = 0;
  for (int j = 0; j < count; ++j) {
    const ForwardKinematicsResult fk = mechanism.forward_kinematics(
        mech_params, scenario.validation_actuators.row(j).transpose(), mechanism.home_pose(),
        scenario.model->forward_kinematics_options());
    if (!fk.ok()) {
      ++stats.fk_failures;
      continue;
    }
    const double dp = position_error(scenario.validation_poses[j], fk.pose);
    const double dr = orientation_error(scenario.validation_poses[j], fk.pose);
    stats.position_mean_mm += dp;
    stats.orientation_mean_rad += dr;
    stats.position_max_mm = std::max(stats.position_max_mm, dp);
    stats.orientation_max_rad = std::max(stats.orientation_max_rad, dr);
    ++ok;
  }
  if (ok > 0) {
    stats.position_mean_mm /= ok;
    stats.orientation_mean_rad /= ok;
  }
  if (stats.fk_failures > 0) {
    // A model that cannot even reach the validation poses is not accurate: say so in numbers.
    stats.position_max_mm = stats.orientation_max_rad = std::numeric_limits<double>::infinity();
  }
  return stats;
}

CalibrationRun run_calibration(const Scenario& scenario, const Solver& solver,
                               SolverOptions options, bool track_iterations,
                               Formulation formulation, const VectorXd& start) {
  const auto problem = scenario.make_problem();
  CalibrationRun run;
  run.before = validation_errors(scenario, scenario.nominal);
  double tracking_seconds = 0;
  std::vector<double> tracking_before;  // tracking time spent before each trace record
  // Outlives the solve: the callback below refers to it.
  const IterationCallback user_callback = options.callback;
  if (track_iterations) {
    options.callback = [&](const IterationRecord& record, const VectorXd& x) {
      tracking_before.push_back(tracking_seconds);
      const auto start = std::chrono::steady_clock::now();
      run.trace_errors.push_back(validation_errors(scenario, problem->full_parameters(x)));
      tracking_seconds +=
          std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
      return user_callback ? user_callback(record, x) : CallbackAction::kContinue;
    };
  }
  VectorXd x = problem->initial_free_parameters();
  if (start.size() > 0) {
    if (start.size() != x.size())
      throw std::invalid_argument("the start has " + std::to_string(start.size()) + " values for " +
                                  std::to_string(x.size()) + " free parameters");
    x = start;
  }
  // The prior stays centred on nominal whatever the start.
  const Prior prior = model_prior(*problem);
  CalibrationSolve solved = solve_calibration(solver, *problem, prior, x, options, formulation);
  // A failed implicit solve's own time, without its tracking: the user waited for it too.
  double failed_implicit_seconds = 0;
  if (solved.failed_implicit) failed_implicit_seconds = solved.failed_implicit->wall_seconds;
  if (track_iterations && solved.failed_implicit) {
    // The trace is the nested solve's: drop the failed implicit solve's records (one per
    // callback) and the tracking time spent on them.
    const std::size_t dropped =
        std::min(solved.failed_implicit->trace.size(), tracking_before.size());
    const double spent =
        dropped < tracking_before.size() ? tracking_before[dropped] : tracking_seconds;
    failed_implicit_seconds = std::max(0.0, failed_implicit_seconds - spent);
    run.trace_errors.erase(run.trace_errors.begin(), run.trace_errors.begin() + dropped);
    tracking_before.erase(tracking_before.begin(), tracking_before.begin() + dropped);
    for (double& before : tracking_before) before -= spent;
    tracking_seconds -= spent;
  }
  run.summary = std::move(solved.summary);
  run.formulation = solved.formulation;
  run.formulation_note = std::move(solved.note);
  run.solve_seconds =
      std::max(0.0, run.summary.wall_seconds - tracking_seconds) + failed_implicit_seconds;
  // The trace's times, too, are those of the solve alone.
  for (std::size_t i = 0; i < run.summary.trace.size() && i < tracking_before.size(); ++i)
    run.summary.trace[i].seconds -= tracking_before[i];
  run.estimate = problem->full_parameters(x);
  run.after = validation_errors(scenario, run.estimate);
  // Per unit: an error in mm and one in rad (or px) are not summed.
  std::map<std::string, std::pair<double, int>> squares;
  for (int i : scenario.free_indices) {
    const std::string& unit = scenario.model->parameters()[i].unit;
    const double d = run.estimate[i] - scenario.truth[i];
    auto& [sum, count] = squares[unit];
    sum += std::pow(unit == kRadian ? wrap_angle(d) : d, 2);
    ++count;
  }
  for (const auto& [unit, sc] : squares)
    run.parameter_rms_errors.set(unit, std::sqrt(sc.first / sc.second));
  run.parameter_rms_error = run.parameter_rms_errors.get(kMillimetre, 0);
  run.parameter_rms_error_rad = run.parameter_rms_errors.get(kRadian, 0);
  return run;
}

StartSpread scenario_start_spread(const Scenario& scenario) {
  const int n = static_cast<int>(scenario.free_indices.size());
  StartSpread spread;
  spread.half_width = VectorXd::Zero(n);
  spread.std = VectorXd::Zero(n);
  for (int c = 0; c < n; ++c) {
    const Parameter& p = scenario.model->parameters()[scenario.free_indices[c]];
    spread.half_width[c] = std::isnan(p.error_half_width) ? scenario.options.param_error_for(p.unit)
                                                          : p.error_half_width;
  }
  return spread;
}

MultiStartResult solve_scenario_starts(const Scenario& scenario, const Solver& solver,
                                       const SolverOptions& options, int starts, int threads) {
  const auto problem = scenario.make_problem();
  MultiStartOptions multi;
  multi.starts = starts;
  multi.seed = scenario.options.seed;
  multi.threads = threads;
  multi.spread = scenario_start_spread(scenario);
  const VectorXd x0 = problem->initial_free_parameters();
  MultiStartResult result;
  with_nested_problem(*problem, model_prior(*problem), [&](const LeastSquaresProblem& nested) {
    result = solve_multi_start(nested, solver, x0, options, multi);
  });
  return result;
}

FitCheck simulated_fit_check(const Scenario& scenario, const CalibrationRun& run) {
  FitCheck f;
  const MeasurementModel& model = *scenario.model;
  const std::shared_ptr<CalibrationProblem> problem = scenario.make_problem();
  bool prior = false;
  for (int i : problem->free_indices()) prior = prior || model.parameters()[i].has_prior();
  const std::vector<std::string> units = model.reading_units();
  const int k = model.num_readings();
  VectorXd noise_std(k);
  for (int i = 0; i < k; ++i) noise_std[i] = scenario.options.noise_for(units[i]) / std::sqrt(3.0);
  if (prior)
    f.not_tested = "a MAP fit: the prior pulls the residuals away from the data's minimum";
  else if (!(noise_std.array() > 0).all())
    f.not_tested = "no simulated noise in some reading's unit";
  if (!f.not_tested.empty()) return f;
  VectorXd x(problem->free_indices().size());
  for (int i = 0; i < x.size(); ++i) x[i] = run.estimate[problem->free_indices()[i]];
  VectorXd r;
  if (!problem->evaluate(x, &r, nullptr)) {
    f.not_tested = "the residuals cannot be computed at the estimate";
    return f;
  }
  // The problem divides by reading_std; the noise drawn is noise_std.
  int measured = 0;
  double sum = 0;
  const Measurements& data = scenario.calibration;
  for (int c = 0; c < data.size(); ++c)
    for (int i = 0; i < k; ++i) {
      if (std::isnan(data.readings(c, i))) continue;
      const double z = r[c * k + i] * model.reading_std()[i] / noise_std[i];
      sum += z * z;
      ++measured;
    }
  f.degrees_of_freedom = measured - static_cast<int>(x.size());
  if (f.degrees_of_freedom <= 0) {
    f.not_tested = "no degrees of freedom (as many readings as parameters)";
    return f;
  }
  f.tested = true;
  f.chi_square = sum;
  f.p_larger = chi_square_upper_tail(sum, f.degrees_of_freedom);
  return f;
}

}  // namespace kincal
