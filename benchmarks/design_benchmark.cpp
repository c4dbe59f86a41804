// kincal-design-benchmark (Google Benchmark): experiment design for the cube hexapod, 60
// measurements chosen from 10^5 candidates (issue 13's target: under 2 s on one core), split
// into drawing the candidates (forward kinematics, reading Jacobian and singularity margin
// of each) and the exchange, per criterion. Results: docs/benchmarks.md.

#include <benchmark/benchmark.h>

#include <memory>

#include "kincal/framework/design/experiment_design.hpp"
#include "kincal/models/presets.hpp"

namespace kincal {
namespace {

DesignOptions hexapod_options(DesignCriterion criterion) {
  DesignOptions o;
  o.criterion = criterion;
  o.count = 60;
  o.num_random = 100000 - 64;  // + the 64 corners of the box = 10^5 candidates
  o.noise_std = VectorXd::Constant(1, 0.0125 / std::sqrt(3.0));
  o.seed = 1;
  return o;
}

struct Prepared {
  std::shared_ptr<MeasurementModel> model = make_cube_hexapod();
  DesignSetup setup;
  DesignCandidates candidates;
  Prepared() {
    const DesignOptions o = hexapod_options(DesignCriterion::kD);
    setup = make_design_setup(*model, o, nullptr);
    candidates = make_design_candidates(*model, setup, o);
  }
};

const Prepared& prepared() {
  static const Prepared p;
  return p;
}

void BM_DesignCandidates(benchmark::State& state) {
  const auto model = make_cube_hexapod();
  const DesignOptions o = hexapod_options(DesignCriterion::kD);
  const DesignSetup setup = make_design_setup(*model, o, nullptr);
  for (auto _ : state) {
    const DesignCandidates c = make_design_candidates(*model, setup, o);
    benchmark::DoNotOptimize(c.rows.data());
    state.counters["candidates"] = c.size();
  }
}
BENCHMARK(BM_DesignCandidates)->Unit(benchmark::kMillisecond)->Iterations(3);

void BM_DesignExchange(benchmark::State& state) {
  const Prepared& p = prepared();
  const auto criterion = static_cast<DesignCriterion>(state.range(0));
  const DesignOptions o = hexapod_options(criterion);
  DesignResult result;
  for (auto _ : state) {
    result = choose_design(p.candidates, p.setup, o);
    benchmark::DoNotOptimize(result.chosen.data());
  }
  state.SetLabel(to_string(criterion));
  state.counters["passes"] = result.passes;
  state.counters["exchanges"] = result.exchanges;
}
// One run per criterion, 3 iterations each (a run is seconds; more would add nothing).
void per_criterion(benchmark::internal::Benchmark* b) {
  for (DesignCriterion c :
       {DesignCriterion::kD, DesignCriterion::kA, DesignCriterion::kE, DesignCriterion::kI})
    b->Arg(static_cast<int>(c));
  b->Unit(benchmark::kMillisecond)->Iterations(3);
}
BENCHMARK(BM_DesignExchange)->Apply(per_criterion);

// Everything `kincal design` does for the hexapod, end to end (setup with its 200 workspace
// samples, candidates, exchange), per criterion: the figure the 2 s target is about.
void BM_DesignEndToEnd(benchmark::State& state) {
  const auto model = make_cube_hexapod();
  const auto criterion = static_cast<DesignCriterion>(state.range(0));
  const DesignOptions o = hexapod_options(criterion);
  for (auto _ : state) {
    const DesignSetup setup = make_design_setup(*model, o, nullptr);
    const DesignCandidates c = make_design_candidates(*model, setup, o);
    const DesignResult result = choose_design(c, setup, o);
    benchmark::DoNotOptimize(result.chosen.data());
  }
  state.SetLabel(to_string(criterion));
}
BENCHMARK(BM_DesignEndToEnd)->Apply(per_criterion);

}  // namespace
}  // namespace kincal

BENCHMARK_MAIN();
