// kincal-implicit-agreement: the nested and the implicit formulation (lm) on the paper's
// cases 1-5 over many seeds, at the tight tolerances of the backends' agreement test. For each
// run: whether both converged, the distance between their end points, the distance between the
// minima reached from each by Newton steps on the nested cost (tests/newton_polish.hpp: the
// minimum resolved to rounding, which the solvers' cost-based stopping tests do not do in the
// flat valley), the size of the last of those steps, the costs, and the mean CPU time and
// iterations of each formulation's solve. Figures: docs/benchmarks.md.
//
//   kincal-implicit-agreement [SEEDS=200] [THREADS=2]
// With KINCAL_AGREEMENT_VERBOSE set, the runs whose minima differ by more than 1e-6 mm are
// listed with their costs and messages.

#include <algorithm>
#include <cstdio>
#include <cstdlib>
#include <limits>
#include <mutex>
#include <vector>

#include "kincal/framework/base/parallel.hpp"
#include "kincal/framework/calibration/calibration_solve.hpp"
#include "kincal/framework/calibration/simulation.hpp"
#include "kincal/framework/least_squares/solver_registry.hpp"
#include "kincal/models/presets.hpp"
#include "tests/newton_polish.hpp"
#include "thread_cpu_time.hpp"

namespace kincal {
namespace {

struct Outcome {
  bool both_converged = false;
  double end_points_mm = 0;               // max |x_implicit - x_nested|
  double minima_mm = 0;                   // the same after Newton steps from each
  double last_step_mm = 0;                // the larger of the two polishings' last steps
  double nested_off_mm = 0;               // the nested end point from its polished minimum
  double implicit_off_mm = 0;             // the implicit end point from its polished minimum
  double cost_ratio = 0;                  // implicit final cost / nested final cost
  double nested_ms = 0, implicit_ms = 0;  // CPU time of each solve (its own thread's)
  int nested_iterations = 0, implicit_iterations = 0;
};

Outcome run(int case_id, std::uint64_t seed) {
  ScenarioOptions o;
  o.num_configurations = paper_case(case_id).num_configurations;
  o.noise_half_width.set(kincal::kMillimetre, paper_case(case_id).noise_half_width);
  o.num_validation = 0;
  o.seed = seed;
  const Scenario scenario = make_scenario(make_cube_hexapod(), o);
  const auto problem = scenario.make_problem();
  const auto lm = SolverRegistry::global().create("lm");
  SolverOptions options;
  options.max_iterations = 500;
  options.function_tolerance = 1e-16;
  options.parameter_tolerance = 1e-14;
  options.gradient_tolerance = 1e-13;
  VectorXd nested_x = problem->initial_free_parameters(), implicit_x = nested_x;
  const double t0 = thread_cpu_ms();
  const CalibrationSolve nested =
      solve_calibration(*lm, *problem, Prior{}, nested_x, options, Formulation::kNested);
  const double t1 = thread_cpu_ms();
  const CalibrationSolve implicit =
      solve_calibration(*lm, *problem, Prior{}, implicit_x, options, Formulation::kImplicit);
  const double t2 = thread_cpu_ms();
  Outcome out;
  out.nested_ms = t1 - t0;
  out.implicit_ms = t2 - t1;
  out.nested_iterations = nested.summary.iterations;
  out.implicit_iterations = implicit.summary.iterations;
  out.both_converged = nested.summary.converged() && implicit.summary.converged() &&
                       implicit.formulation == Formulation::kImplicit;
  out.end_points_mm = (implicit_x - nested_x).lpNorm<Eigen::Infinity>();
  double step_from_implicit = 0, step_from_nested = 0;
  const VectorXd from_implicit =
      testing::newton_polished(*problem, implicit_x, &step_from_implicit);
  const VectorXd from_nested = testing::newton_polished(*problem, nested_x, &step_from_nested);
  out.minima_mm = (from_implicit - from_nested).lpNorm<Eigen::Infinity>();
  out.last_step_mm = std::max(step_from_implicit, step_from_nested);
  out.nested_off_mm = (nested_x - from_nested).lpNorm<Eigen::Infinity>();
  out.implicit_off_mm = (implicit_x - from_implicit).lpNorm<Eigen::Infinity>();
  out.cost_ratio = implicit.summary.final_cost / nested.summary.final_cost;
  if (std::getenv("KINCAL_AGREEMENT_VERBOSE") && out.minima_mm > 1e-6)
    std::printf(
        "  case %d seed %llu: costs nested %.15g implicit %.15g polished %.15g %.15g; %s | %s\n",
        case_id, static_cast<unsigned long long>(seed), nested.summary.final_cost,
        implicit.summary.final_cost, problem->cost(from_nested), problem->cost(from_implicit),
        nested.summary.message.c_str(), implicit.summary.message.c_str());
  return out;
}

}  // namespace
}  // namespace kincal

int main(int argc, char** argv) {
  using namespace kincal;
  const int seeds = argc > 1 ? std::atoi(argv[1]) : 200;
  const int threads = argc > 2 ? std::atoi(argv[2]) : 2;
  std::printf(
      "case seeds both_converged end_points_max_mm end_points_median_mm minima_max_mm "
      "last_newton_step_max_mm nested_off_max_mm implicit_off_max_mm cost_ratio_max "
      "nested_ms_mean implicit_ms_mean nested_iterations_mean implicit_iterations_mean\n");
  for (int case_id = 1; case_id <= 5; ++case_id) {
    std::vector<Outcome> outcomes(static_cast<std::size_t>(seeds));
    parallel_for(seeds, threads, [&](int i) {
      outcomes[static_cast<std::size_t>(i)] = run(case_id, static_cast<std::uint64_t>(i + 1));
    });
    int converged = 0;
    double minima = 0, last_step = 0, nested_off = 0, implicit_off = 0, ratio = 0;
    double nested_ms = 0, implicit_ms = 0, nested_iterations = 0, implicit_iterations = 0;
    std::vector<double> ends;
    for (const Outcome& o : outcomes) {
      converged += o.both_converged;
      ends.push_back(o.end_points_mm);
      minima = std::max(minima, o.minima_mm);
      last_step = std::max(last_step, o.last_step_mm);
      nested_off = std::max(nested_off, o.nested_off_mm);
      implicit_off = std::max(implicit_off, o.implicit_off_mm);
      ratio = std::max(ratio, o.cost_ratio);
      nested_ms += o.nested_ms / seeds;
      implicit_ms += o.implicit_ms / seeds;
      nested_iterations += static_cast<double>(o.nested_iterations) / seeds;
      implicit_iterations += static_cast<double>(o.implicit_iterations) / seeds;
    }
    std::sort(ends.begin(), ends.end());
    std::printf("%d %d %d %.3g %.3g %.3g %.3g %.3g %.3g %.12g %.3f %.3f %.2f %.2f\n", case_id,
                seeds, converged, ends.back(), ends[ends.size() / 2], minima, last_step, nested_off,
                implicit_off, ratio, nested_ms, implicit_ms, nested_iterations,
                implicit_iterations);
  }
  return 0;
}
