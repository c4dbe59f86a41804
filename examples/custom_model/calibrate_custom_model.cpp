// Example: a mechanism and a sensor written outside kincal, registered at start-up, then
// used like the built-in ones: a model file written and read back, and a noise-free
// simulated calibration with every least-squares backend of this build, which must recover
// the truth. docs/extending.md walks through the code.
//
//   build/examples/calibrate_custom_model

#include <cmath>
#include <cstdio>
#include <kincal/framework/calibration/simulation.hpp>
#include <kincal/framework/extension/model_registry.hpp>
#include <kincal/framework/least_squares/solver_registry.hpp>
#include <kincal/models/model_io.hpp>

#include "example_models.hpp"

int main() {
  using namespace kincal;
  example::register_example_models(ModelRegistry::global());

  // Through a model file and back, as `kincal model --preset two-link-demo` would write it.
  const auto preset = ModelRegistry::global().make_preset("two-link-demo");
  const Json file = model_to_json(*preset, preset->parameters().nominal_values());
  std::printf("%s\n", file.dump(2).c_str());
  const auto model = model_from_json(file, "two-link-demo.json");

  ScenarioOptions options;  // 30 configurations, errors 5 mm / 0.01 rad, no noise
  options.seed = 7;
  options.num_validation = 50;
  const Scenario scenario = make_scenario(model, options);
  int failures = 0;
  for (const auto& info : SolverRegistry::global().list()) {
    if (info.kind != SolverKind::kLeastSquares) continue;
    const auto solver = SolverRegistry::global().create(info.name);
    const CalibrationRun run = run_calibration(scenario, *solver, SolverOptions{}, false);
    double worst = 0;
    for (int i : scenario.free_indices)
      worst = std::max(worst, std::abs(run.estimate[i] - scenario.truth[i]));
    const bool ok = run.summary.converged() && worst < 1e-6;
    failures += !ok;
    std::printf("%-6s %-10s worst parameter error %.2e, pose error %.3f -> %.2e mm\n",
                info.name.c_str(), to_string(run.summary.termination), worst,
                run.before.position_mean_mm, run.after.position_mean_mm);
  }
  return failures == 0 ? 0 : 1;
}
