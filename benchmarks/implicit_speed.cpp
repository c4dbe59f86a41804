// kincal-implicit-speed: lm on the implicit formulation against lm on the nested one, at the
// default tolerances, over many seeds of the paper's cases 2-5 from a chosen parameter error:
// mean CPU time and iterations of each, how many converged, and whether the implicit solve
// ended in the nested solve's minimum (its final cost within 1e-6, relative) or in another,
// lower or higher, and on how many it failed and the nested solve from the start replaced it
// (calibration_solve.hpp; the time includes both). lm backend options given as KEY=VALUE apply to
// the implicit solve only (the trust-region schedule it takes, docs/solvers.md); the nested one
// runs at the defaults. Figures: docs/benchmarks.md ("Implicit formulation").
//
//   kincal-implicit-speed [SEEDS=200] [PARAM_ERROR_MM=5] [KEY=VALUE ...]

#include <cstdio>
#include <cstdlib>
#include <map>
#include <string>

#include "kincal/framework/calibration/calibration_solve.hpp"
#include "kincal/framework/calibration/simulation.hpp"
#include "kincal/framework/least_squares/solver_registry.hpp"
#include "kincal/models/presets.hpp"
#include "thread_cpu_time.hpp"

int main(int argc, char** argv) {
  using namespace kincal;
  const int seeds = argc > 1 ? std::atoi(argv[1]) : 200;
  const double param_error = argc > 2 ? std::atof(argv[2]) : 5;
  std::map<std::string, std::string> settings;
  for (int i = 3; i < argc; ++i) {
    const std::string entry = argv[i];
    const auto equals = entry.find('=');
    if (equals == std::string::npos) {
      std::fprintf(stderr, "kincal-implicit-speed: '%s' is not KEY=VALUE\n", argv[i]);
      return 2;
    }
    settings[entry.substr(0, equals)] = entry.substr(equals + 1);
  }
  const auto lm = SolverRegistry::global().create("lm");
  SolverOptions implicit_options;
  implicit_options.backend = lm->parse_settings(settings);
  std::printf(
      "case seeds nested_ms nested_iterations nested_converged implicit_ms implicit_iterations "
      "implicit_converged fell_back same_minimum lower higher\n");
  for (int case_id = 2; case_id <= 5; ++case_id) {
    double nested_ms = 0, implicit_ms = 0, nested_iterations = 0, implicit_iterations = 0;
    int nested_converged = 0, implicit_converged = 0, fell_back = 0, same = 0, lower = 0,
        higher = 0;
    for (int seed = 1; seed <= seeds; ++seed) {
      ScenarioOptions o;
      o.num_configurations = paper_case(case_id).num_configurations;
      o.noise_half_width.set(kincal::kMillimetre, paper_case(case_id).noise_half_width);
      o.param_error_half_width.set(kincal::kMillimetre, param_error);
      o.num_validation = 0;
      o.seed = static_cast<std::uint64_t>(seed);
      const Scenario scenario = make_scenario(make_cube_hexapod(), o);
      const auto problem = scenario.make_problem();
      VectorXd nested_x = problem->initial_free_parameters(), implicit_x = nested_x;
      const double t0 = thread_cpu_ms();
      const CalibrationSolve nested =
          solve_calibration(*lm, *problem, Prior{}, nested_x, {}, Formulation::kNested);
      const double t1 = thread_cpu_ms();
      const CalibrationSolve implicit = solve_calibration(*lm, *problem, Prior{}, implicit_x,
                                                          implicit_options, Formulation::kImplicit);
      const double t2 = thread_cpu_ms();
      fell_back += implicit.failed_implicit.has_value();
      if (implicit.formulation != Formulation::kImplicit && !implicit.failed_implicit) {
        std::fprintf(stderr, "kincal-implicit-speed: %s\n", implicit.note.c_str());
        return 1;
      }
      nested_ms += (t1 - t0) / seeds;
      implicit_ms += (t2 - t1) / seeds;
      nested_iterations += static_cast<double>(nested.summary.iterations) / seeds;
      const int failed_iterations =
          implicit.failed_implicit ? implicit.failed_implicit->iterations : 0;
      implicit_iterations +=
          static_cast<double>(implicit.summary.iterations + failed_iterations) / seeds;
      nested_converged += nested.summary.converged();
      implicit_converged +=
          implicit.formulation == Formulation::kImplicit && implicit.summary.converged();
      const double a = nested.summary.final_cost, b = implicit.summary.final_cost;
      if (b > a * (1 + 1e-6))
        ++higher;
      else if (b < a * (1 - 1e-6))
        ++lower;
      else
        ++same;
    }
    std::printf("%d %d %.3f %.2f %d %.3f %.2f %d %d %d %d %d\n", case_id, seeds, nested_ms,
                nested_iterations, nested_converged, implicit_ms, implicit_iterations,
                implicit_converged, fell_back, same, lower, higher);
  }
  return 0;
}
