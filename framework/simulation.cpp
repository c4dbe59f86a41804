#include "kincal/framework/simulation.hpp"

#include <algorithm>
#include <chrono>
#include <cmath>
#include <limits>
#include <stdexcept>

#include "kincal/framework/random.hpp"

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

// Draws `count` configurations around `home_q` that the true geometry can reach; fills
// their true poses.
void draw_configurations(const MeasurementModel& model, const VectorXd& truth,
                         const VectorXd& home_q, double range, int count, Random& rng,
                         MatrixXd& actuators, std::vector<Pose>& poses) {
  const Mechanism& mechanism = model.mechanism();
  const auto mech_truth = truth.head(mechanism.num_parameters());
  const int na = mechanism.num_actuators();
  actuators.resize(count, na);
  poses.assign(count, Pose{});
  VectorXd q(na);
  // 64 bits: 1000 attempts per configuration overflow an int beyond 2.1 million of them.
  const long long max_attempts = 1000LL * std::max(count, 1);
  long long attempts = 0;
  for (int j = 0; j < count;) {
    if (++attempts > max_attempts)
      throw std::runtime_error(
          "could not draw reachable configurations: forward kinematics of the true model "
          "keeps failing (is the configuration range too large?)");
    for (int i = 0; i < na; ++i) q[i] = home_q[i] + rng.symmetric(range);
    const ForwardKinematicsResult fk = mechanism.forward_kinematics(
        mech_truth, q, mechanism.home_pose(), model.forward_kinematics_options());
    if (!fk.ok()) continue;
    actuators.row(j) = q.transpose();
    poses[j] = fk.pose;
    ++j;
  }
}

}  // namespace

Scenario make_scenario(std::shared_ptr<const MeasurementModel> model,
                       const ScenarioOptions& options) {
  if (options.num_configurations < 1)
    throw std::invalid_argument("the number of configurations must be at least 1");
  if (options.noise_half_width < 0 || options.param_error_half_width < 0 ||
      options.config_range < 0 || options.num_validation < 0)
    throw std::invalid_argument("noise, parameter error, range and validation size must be >= 0");
  Scenario s;
  s.model = model;
  s.options = options;
  s.nominal = model->parameters().nominal_values();
  s.free_indices = model->parameters().free_indices();

  Random truth_rng(derive_seed(options.seed, kTruthStream));
  s.truth = s.nominal;
  for (int i : s.free_indices) s.truth[i] += truth_rng.symmetric(options.param_error_half_width);

  // Commanded actuator values at home come from the nominal model, as a controller would.
  const Mechanism& mechanism = model->mechanism();
  VectorXd home_q(mechanism.num_actuators());
  mechanism.inverse_kinematics(s.nominal.head(mechanism.num_parameters()), mechanism.home_pose(),
                               home_q);

  Random config_rng(derive_seed(options.seed, kConfigStream));
  std::vector<Pose> calibration_poses;
  draw_configurations(*model, s.truth, home_q, options.config_range, options.num_configurations,
                      config_rng, s.calibration.actuators, calibration_poses);

  Random noise_rng(derive_seed(options.seed, kNoiseStream));
  const int k = model->num_readings();
  s.calibration.readings.resize(options.num_configurations, k);
  VectorXd reading(k);
  for (int j = 0; j < options.num_configurations; ++j) {
    model->predict_at_pose(s.truth, calibration_poses[j], reading);
    for (int i = 0; i < k; ++i) reading[i] += noise_rng.symmetric(options.noise_half_width);
    s.calibration.readings.row(j) = reading.transpose();
  }

  Random validation_rng(derive_seed(options.seed, kValidationStream));
  draw_configurations(*model, s.truth, home_q, options.config_range, options.num_validation,
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
                               SolverOptions options, bool track_iterations) {
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
  run.summary = solver.solve(*problem, x, options);
  run.solve_seconds = std::max(0.0, run.summary.wall_seconds - tracking_seconds);
  // The trace's times, too, are those of the solve alone.
  for (std::size_t i = 0; i < run.summary.trace.size() && i < tracking_before.size(); ++i)
    run.summary.trace[i].seconds -= tracking_before[i];
  run.estimate = problem->full_parameters(x);
  run.after = validation_errors(scenario, run.estimate);
  double sum = 0;
  for (int i : scenario.free_indices) sum += std::pow(run.estimate[i] - scenario.truth[i], 2);
  run.parameter_rms_error =
      scenario.free_indices.empty() ? 0.0 : std::sqrt(sum / scenario.free_indices.size());
  return run;
}

}  // namespace kincal
