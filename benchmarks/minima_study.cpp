// kincal-minima-study: how often lm ends in a local minimum from far starts on the paper's
// cases, and how many starts (kincal simulate --starts N) find the global one. For each case
// and seed S (the scenario of `kincal simulate --case C --param-error E --seed S`): the
// starts 0..K-1 that --starts K would run, and a reference solve from the true parameters.
// The global minimum is the lowest cost of all of them; a run with N starts finds it when its
// best start ends there. See docs/benchmarks.md, "Local minima".

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <cstdlib>
#include <ctime>
#include <numeric>
#include <stdexcept>
#include <string>
#include <vector>

#include "kincal/framework/base/parallel.hpp"
#include "kincal/framework/calibration/multi_start.hpp"
#include "kincal/framework/calibration/simulation.hpp"
#include "kincal/framework/least_squares/solver_registry.hpp"
#include "kincal/models/presets.hpp"

namespace {

using namespace kincal;

const char* const kUsage =
    "usage: kincal-minima-study [options]\n"
    "  --cases LIST        paper cases (default 2,3,4,5)\n"
    "  --seeds N           seeds 1..N per case (default 200)\n"
    "  --param-error E     parameter error half-width, mm (default 20)\n"
    "  --starts K          starts per seed; N = 1..K are reported (default 8)\n"
    "  --solver NAME       (default lm)\n"
    "  --threads N         0 = all cores (default 0)\n"
    "  --list              one line per seed whose start 0 misses the global minimum\n"
    "N = 1, 2, 4, ... up to K are reported: the starts of --starts N are the first N of K.\n";

struct SeedResult {
  std::vector<bool> start_global;  // per start: ended at the global minimum
  std::vector<int> start_minimum;  // per start: its distinct minimum (-1: no solution)
  std::vector<double> start_rms;   // per start: parameter RMS error of its solution, mm
  std::vector<double> start_cost;  // per start: final cost, +inf without a solution
  double global_rms = 0;           // parameter RMS error at the global minimum, mm
  double delta_chi_square = 0;     // 2 (cost of start 0 - global cost) / noise variance
  double fit_p = 1;                // fit check P(larger) at start 0's solution
  double cpu_seconds = 0;          // CPU time of the starts
};

double thread_cpu_seconds() {
  timespec t{};
  clock_gettime(CLOCK_THREAD_CPUTIME_ID, &t);
  return static_cast<double>(t.tv_sec) + 1e-9 * static_cast<double>(t.tv_nsec);
}

double parameter_rms(const Scenario& scenario, const VectorXd& estimate) {
  double sum = 0;
  for (int i : scenario.free_indices) sum += std::pow(estimate[i] - scenario.truth[i], 2);
  return std::sqrt(sum / static_cast<double>(scenario.free_indices.size()));
}

double median(std::vector<double> v) {
  if (v.empty()) return NAN;
  std::nth_element(v.begin(), v.begin() + v.size() / 2, v.end());
  return v[v.size() / 2];
}

}  // namespace

int main(int argc, char** argv) {
  std::vector<int> cases = {2, 3, 4, 5};
  int seeds = 200, starts = 8, threads = 0;
  double param_error = 20;
  std::string solver_name = "lm";
  bool list = false;
  try {
    for (int i = 1; i < argc; ++i) {
      const std::string arg = argv[i];
      if (arg == "--help") {
        std::fputs(kUsage, stdout);
        return 0;
      }
      if (arg == "--list") {
        list = true;
        continue;
      }
      if (i + 1 >= argc) throw std::invalid_argument(arg + ": missing value (see --help)");
      const std::string value = argv[++i];
      if (arg == "--cases") {
        cases.clear();
        for (std::size_t p = 0; p <= value.size();) {
          const std::size_t q = std::min(value.find(',', p), value.size());
          cases.push_back(std::stoi(value.substr(p, q - p)));
          p = q + 1;
        }
      } else if (arg == "--seeds") {
        seeds = std::stoi(value);
      } else if (arg == "--param-error") {
        param_error = std::stod(value);
      } else if (arg == "--starts") {
        starts = std::stoi(value);
      } else if (arg == "--solver") {
        solver_name = value;
      } else if (arg == "--threads") {
        threads = std::stoi(value);
      } else {
        throw std::invalid_argument("unknown option '" + arg + "' (see --help)");
      }
    }
    if (seeds < 1 || starts < 1) throw std::invalid_argument("--seeds and --starts must be >= 1");
    const auto model = make_cube_hexapod();
    const auto solver = SolverRegistry::global().create(solver_name);
    std::printf("kincal-minima-study: %s, parameter errors ±%g mm, seeds 1-%d, %d starts\n",
                solver_name.c_str(), param_error, seeds, starts);
    for (int c : cases) {
      std::vector<SeedResult> results(seeds);
      parallel_for(seeds, threads, [&](int t) {
        ScenarioOptions so;
        so.noise_half_width.set(kincal::kMillimetre, paper_case(c).noise_half_width);
        so.num_configurations = paper_case(c).num_configurations;
        so.param_error_half_width.set(kincal::kMillimetre, param_error);
        so.num_validation = 1;
        so.seed = static_cast<std::uint64_t>(t + 1);
        const Scenario scenario = make_scenario(model, so);
        const auto problem = scenario.make_problem();
        SeedResult& r = results[t];
        const double t0 = thread_cpu_seconds();
        const MultiStartResult m = solve_scenario_starts(scenario, *solver, {}, starts, 1);
        r.cpu_seconds = thread_cpu_seconds() - t0;
        // The reference: a solve from the true parameters.
        VectorXd x(scenario.free_indices.size());
        for (int i = 0; i < x.size(); ++i) x[i] = scenario.truth[scenario.free_indices[i]];
        const Summary truth_run = solver->solve(*problem, x, {});
        double global = truth_run.final_cost;
        r.global_rms = parameter_rms(scenario, problem->full_parameters(x));
        for (const StartOutcome& o : m.starts)
          if (reached_solution(o.summary) && o.summary.final_cost < global) {
            global = o.summary.final_cost;
            r.global_rms = parameter_rms(scenario, problem->full_parameters(o.x));
          }
        // The same minimum as MultiStartResult groups them (relative cost and its floor).
        const double floor = kSameCostFloor * m.starts[0].summary.initial_cost;
        for (const StartOutcome& o : m.starts) {
          const bool ok = reached_solution(o.summary);
          r.start_global.push_back(ok && o.summary.final_cost <=
                                             global * (1 + kSameCostRelative) + floor);
          r.start_minimum.push_back(o.minimum);
          r.start_rms.push_back(parameter_rms(scenario, problem->full_parameters(o.x)));
          r.start_cost.push_back(ok ? o.summary.final_cost : INFINITY);
        }
        const double variance = std::pow(so.noise_for(kincal::kMillimetre), 2) / 3.0;
        r.delta_chi_square = 2.0 * (m.starts[0].summary.final_cost - global) / variance;
        CalibrationRun run;
        run.estimate = problem->full_parameters(m.starts[0].x);
        r.fit_p = simulated_fit_check(scenario, run).p_larger;
      });
      int local0 = 0, flagged = 0;
      std::vector<double> cpu, delta, rms0, rms_global;
      for (int t = 0; t < seeds; ++t) {
        const SeedResult& r = results[t];
        local0 += !r.start_global[0];
        flagged += r.fit_p < kFitCheckProbability;
        cpu.push_back(1e3 * r.cpu_seconds / starts);
        if (!r.start_global[0]) {
          delta.push_back(r.delta_chi_square);
          rms0.push_back(r.start_rms[0]);
          rms_global.push_back(r.global_rms);
        }
        if (list && !r.start_global[0]) {
          std::printf(
              "  case %d seed %d: start 0 delta chi-square %.3g, fit check P %.3g, "
              "parameter RMS error %.3g mm (global minimum: %.3g mm), starts there:",
              c, t + 1, r.delta_chi_square, r.fit_p, r.start_rms[0], r.global_rms);
          for (int n = 0; n < starts; ++n)
            if (r.start_global[n]) std::printf(" %d", n);
          std::printf("\n");
        }
      }
      std::printf(
          "case %d: start 0 (one start) misses the global minimum on %d of %d seeds, "
          "the fit check flags %d; on those, median delta chi-square %.3g, mean "
          "parameter RMS error %.3g mm at start 0's minimum, %.3g mm at the global; "
          "CPU %.2f ms per start (median)\n",
          c, local0, seeds, flagged, median(delta),
          rms0.empty() ? NAN : std::accumulate(rms0.begin(), rms0.end(), 0.0) / rms0.size(),
          rms_global.empty()
              ? NAN
              : std::accumulate(rms_global.begin(), rms_global.end(), 0.0) / rms_global.size(),
          median(cpu));
      std::printf(
          "  N starts | seeds missing the global | of them flagged (several minima among "
          "the N) | unflagged\n");
      for (int n = 1; n <= starts; n *= 2) {
        int missed = 0, missed_flagged = 0;
        std::vector<double> rms;
        for (const SeedResult& r : results) {
          // The estimate of --starts n: the lowest cost among the first n (first start on ties).
          int best = 0;
          for (int k = 1; k < n; ++k)
            if (r.start_cost[k] < r.start_cost[best] * (1 - kSameCostRelative)) best = k;
          rms.push_back(r.start_rms[best]);
          bool found = false, several = false;
          for (int k = 0; k < n; ++k) {
            found = found || r.start_global[k];
            several = several || r.start_minimum[k] != r.start_minimum[0];
          }
          missed += !found;
          missed_flagged += !found && several;
        }
        std::sort(rms.begin(), rms.end());
        std::printf("  %8d | %24d | %43d | %9d | %.3g, %.3g\n", n, missed, missed_flagged,
                    missed - missed_flagged,
                    std::accumulate(rms.begin(), rms.end(), 0.0) / static_cast<double>(rms.size()),
                    rms[static_cast<std::size_t>(0.9 * static_cast<double>(rms.size() - 1))]);
      }
      std::fflush(stdout);
    }
  } catch (const std::exception& e) {
    std::fprintf(stderr, "kincal-minima-study: %s\n", e.what());
    return 2;
  }
  return 0;
}
