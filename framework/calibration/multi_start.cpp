#include "kincal/framework/calibration/multi_start.hpp"

#include <algorithm>
#include <cmath>
#include <mutex>
#include <numeric>
#include <stdexcept>

#include "kincal/framework/base/parallel.hpp"
#include "kincal/framework/base/random.hpp"
#include "kincal/framework/kinematics/units.hpp"

namespace kincal {

namespace {

// Streams of derive_seed(seed, k) are the starts'; this offset keeps them apart from the
// scenario's streams when a command passes its scenario seed.
constexpr std::uint64_t kStartStreamBase = 1000;

// Box-Muller on the 53-bit uniforms: the same numbers on every standard library.
double standard_normal(Random& rng) {
  const double u1 = 1.0 - rng.uniform01();  // (0, 1]: log is finite
  const double u2 = rng.uniform01();
  return std::sqrt(-2.0 * std::log(u1)) * std::cos(2.0 * M_PI * u2);
}

// RMS over the parameters with a spread of (a - b) / scale.
double scaled_distance(const VectorXd& a, const VectorXd& b, const VectorXd& scale) {
  double sum = 0;
  int count = 0;
  for (int i = 0; i < a.size(); ++i) {
    if (!(scale[i] > 0)) continue;
    sum += std::pow((a[i] - b[i]) / scale[i], 2);
    ++count;
  }
  return count ? std::sqrt(sum / count) : 0.0;
}

}  // namespace

VectorXd StartSpread::scale() const {
  VectorXd s(half_width.size());
  for (int i = 0; i < s.size(); ++i)
    s[i] = half_width[i] > 0 ? half_width[i] / std::sqrt(3.0) : (std[i] > 0 ? std[i] : 0.0);
  return s;
}

StartSpread model_start_spread(const MeasurementModel& model, const std::vector<int>& free_indices,
                               double default_half_width_mm, double default_half_width_rad) {
  StartSpread spread;
  const int n = static_cast<int>(free_indices.size());
  spread.half_width = VectorXd::Zero(n);
  spread.std = VectorXd::Zero(n);
  for (int c = 0; c < n; ++c) {
    const Parameter& p = model.parameters()[free_indices[c]];
    if (!std::isnan(p.error_half_width)) {
      spread.half_width[c] = p.error_half_width;
    } else if (p.has_prior()) {
      spread.std[c] = p.prior_std;
    } else {
      spread.half_width[c] = p.unit == kRadian ? default_half_width_rad : default_half_width_mm;
      spread.assumed = true;
    }
  }
  return spread;
}

bool reached_solution(const Summary& summary) {
  return summary.termination == TerminationType::kConverged ||
         summary.termination == TerminationType::kMaxIterations;
}

VectorXd draw_start(const VectorXd& x0, const StartSpread& spread, std::uint64_t seed, int k) {
  if (spread.half_width.size() != x0.size() || spread.std.size() != x0.size())
    throw std::invalid_argument("the start spread has " + std::to_string(spread.half_width.size()) +
                                " entries for " + std::to_string(x0.size()) + " parameters");
  VectorXd x = x0;
  if (k == 0) return x;
  Random rng(derive_seed(seed, kStartStreamBase + static_cast<std::uint64_t>(k)));
  for (int i = 0; i < x.size(); ++i) {
    // Both draws are always taken, so a parameter's draw does not depend on the others' kinds.
    const double u = rng.symmetric(1.0);
    const double g = standard_normal(rng);
    if (spread.half_width[i] > 0)
      x[i] += u * spread.half_width[i];
    else if (spread.std[i] > 0)
      x[i] += g * spread.std[i];
  }
  return x;
}

MultiStartResult solve_multi_start(const LeastSquaresProblem& problem, const Solver& solver,
                                   const VectorXd& x0, const SolverOptions& options,
                                   const MultiStartOptions& multi) {
  if (multi.starts < 1) throw std::invalid_argument("the number of starts must be at least 1");
  MultiStartResult result;
  result.starts.resize(multi.starts);
  for (int k = 0; k < multi.starts; ++k) {
    VectorXd start = draw_start(x0, multi.spread, multi.seed, k);
    if (options.lower_bounds && options.upper_bounds)
      start = start.cwiseMax(*options.lower_bounds).cwiseMin(*options.upper_bounds);
    result.starts[k].start = start;
  }
  SolverOptions one = options;
  // The caller's callback sees every start's iterations, one call at a time; a stop it asks
  // for (the Python bindings' Ctrl-C) stops them all.
  std::mutex callback_mutex;
  bool stop = false;
  if (options.callback)
    one.callback = [&](const IterationRecord& record, const VectorXd& x) {
      std::lock_guard<std::mutex> lock(callback_mutex);
      if (!stop) stop = options.callback(record, x) == CallbackAction::kStop;
      return stop ? CallbackAction::kStop : CallbackAction::kContinue;
    };
  one.verbosity = 0;
  one.num_threads = 1;  // the starts are the parallel work
  // Debian's Ipopt solves with sequential MUMPS, whose Fortran globals are not thread-safe.
  const int threads = solver.name() == "ipopt" ? 1 : multi.threads;
  parallel_for(multi.starts, threads, [&](int k) {
    StartOutcome& o = result.starts[k];
    o.x = o.start;
    o.summary = solver.solve(problem, o.x, one);
  });

  // Group in ascending cost (ties by start): each solution joins the first minimum it matches.
  std::vector<int> order;
  for (int k = 0; k < multi.starts; ++k) {
    if (reached_solution(result.starts[k].summary))
      order.push_back(k);
    else
      ++result.unsolved;
  }
  std::stable_sort(order.begin(), order.end(), [&](int a, int b) {
    return result.starts[a].summary.final_cost < result.starts[b].summary.final_cost;
  });
  const VectorXd scale = multi.spread.scale();
  const double floor = kSameCostFloor * result.starts[0].summary.initial_cost;
  for (int k : order) {
    StartOutcome& o = result.starts[k];
    const double cost = o.summary.final_cost;
    for (std::size_t m = 0; m < result.minima.size() && o.minimum < 0; ++m) {
      const DistinctMinimum& d = result.minima[m];
      const bool same_cost = std::abs(cost - d.cost) <= kSameCostRelative * cost + floor;
      if (same_cost && scaled_distance(o.x, d.x, scale) <= kSameMinimumDistance)
        o.minimum = static_cast<int>(m);
    }
    if (o.minimum < 0) {
      o.minimum = static_cast<int>(result.minima.size());
      result.minima.push_back({cost, o.x, {}, 0.0});
    }
    result.minima[o.minimum].starts.push_back(k);
  }
  for (DistinctMinimum& d : result.minima) {
    std::sort(d.starts.begin(), d.starts.end());
    d.distance_to_best = scaled_distance(d.x, result.minima[0].x, scale);
  }
  // The first start at the best minimum: start 0 when it is there, so that more starts change
  // the estimate only when they find a lower minimum.
  if (!result.minima.empty()) result.best_start = result.minima[0].starts.front();
  result.stopped = stop;
  if (stop && result.minima.empty()) {
    // None reached a solution before the stop: the lowest cost reached, as one stopped solve
    // returns its best point.
    for (int k = 1; k < multi.starts; ++k)
      if (result.starts[k].summary.final_cost < result.starts[result.best_start].summary.final_cost)
        result.best_start = k;
  }
  return result;
}

Summary MultiStartResult::estimate_summary() const {
  Summary summary = starts[static_cast<std::size_t>(best_start)].summary;
  if (stopped) {
    summary.termination = TerminationType::kUserStopped;
    summary.message = "stopped by the callback before every start had ended; the best of " +
                      std::to_string(starts.size()) +
                      " starts so far (this one: " + summary.message + ")";
  }
  return summary;
}

StartsReport single_start_report(const VectorXd& x0, const VectorXd& x, const Summary& summary,
                                 std::uint64_t seed) {
  StartsReport report;
  report.seed = seed;
  report.spread_from = "the model's values only";
  StartOutcome outcome{x0, x, summary, -1};
  if (reached_solution(summary)) {
    outcome.minimum = 0;
    report.result.minima.push_back({summary.final_cost, x, {0}, 0.0});
  } else {
    report.result.unsolved = 1;
  }
  report.result.starts.push_back(outcome);
  return report;
}

}  // namespace kincal
