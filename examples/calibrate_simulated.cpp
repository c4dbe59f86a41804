// Example: calibrate the paper's cube hexapod from simulated gauge readings with the library
// API, then print how far the calibrated model is from the truth.
//
//   build/examples/calibrate_simulated [solver-name]

#include <cstdio>

#include "kincal/framework/calibration/simulation.hpp"
#include "kincal/framework/least_squares/solver_registry.hpp"
#include "kincal/models/presets.hpp"

int main(int argc, char** argv) {
  using namespace kincal;
  const std::string solver_name = argc > 1 ? argv[1] : "gn";

  // The paper's case 3: 40 configurations, gauge noise U[-1.25, 1.25] um.
  ScenarioOptions options;
  options.num_configurations = paper_case(3).num_configurations;
  options.noise_half_width.set(kincal::kMillimetre, paper_case(3).noise_half_width);
  options.seed = 2024;
  const Scenario scenario = make_scenario(make_cube_hexapod(), options);

  const auto solver = SolverRegistry::global().create(solver_name);
  SolverOptions solver_options;
  solver_options.max_iterations = 50;
  const CalibrationRun run = run_calibration(scenario, *solver, solver_options);

  std::printf("%s\n", run.summary.brief_report().c_str());
  std::printf("validation position error: %.4f mm before, %.4f mm after (mean of %d poses)\n",
              run.before.position_mean_mm, run.after.position_mean_mm, options.num_validation);
  for (int i : scenario.free_indices)
    std::printf("  %-18s true %9.4f  estimate %9.4f\n",
                scenario.model->parameters()[i].name.c_str(), scenario.truth[i], run.estimate[i]);
  return run.summary.converged() ? 0 : 1;
}
