#include "kincal/problems/suite.hpp"

#include <cmath>

namespace kincal::problems {

std::vector<SuiteStart> suite_starts(const TestProblem& problem) {
  std::vector<SuiteStart> starts;
  for (const double factor : {1.0, 10.0, 100.0}) {
    SuiteStart start;
    start.label = factor == 1 ? "x0" : std::to_string(static_cast<int>(factor)) + "x0";
    start.x = factor * problem.start();
    bool seen = false;
    for (const auto& earlier : starts) seen = seen || earlier.x == start.x;
    if (seen) continue;
    VectorXd r;
    start.evaluable = problem.evaluate(start.x, &r, nullptr, &start.why_not_evaluable);
    starts.push_back(std::move(start));
  }
  return starts;
}

const char* to_string(Outcome outcome) {
  switch (outcome) {
    case Outcome::kPublishedMinimum:
      return "published minimum";
    case Outcome::kPublishedLocal:
      return "published local minimum";
    case Outcome::kElsewhere:
      return "elsewhere";
  }
  return "elsewhere";
}

bool reaches(double cost, double published) {
  if (!std::isfinite(cost)) return false;
  if (published == 0) return cost <= kZeroCostTolerance;
  return cost <= published * (1 + kRelativeCostTolerance);
}

Outcome classify(const TestProblem& problem, double cost) {
  if (reaches(cost, problem.published_minimum())) return Outcome::kPublishedMinimum;
  for (const auto& minimum : problem.minima())
    if (!minimum.global && std::abs(cost - minimum.cost) <= kRelativeCostTolerance * minimum.cost)
      return Outcome::kPublishedLocal;
  return Outcome::kElsewhere;
}

}  // namespace kincal::problems
