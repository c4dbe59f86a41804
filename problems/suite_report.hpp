#pragma once
// The renderings of a run of the test-problem suite (suite_runner.hpp), for `kincal
// solver-suite` and anyone who runs the suite from the library: the problem list, one line
// per case, one line per backend's tally, and the JSON of a backend's results.

#include <memory>
#include <nlohmann/json.hpp>
#include <string>
#include <vector>

#include "kincal/problems/suite_runner.hpp"

namespace kincal::problems {

/// The problems with their sizes, starts ("(!)" where the cost overflows) and published
/// minima, a header line and a footnote.
std::string problem_list_text(const std::vector<std::shared_ptr<const TestProblem>>& problems);

/// One case as JSON: problem, start, size, published minimum, and for an evaluable start the
/// termination, counts, costs, outcome, time and the contract's verdict.
nlohmann::json to_json(const SuiteCaseResult& result);

/// A backend's tally and every case: the "solvers" entry of solver-suite's JSON.
nlohmann::json suite_json(const std::string& solver, const SuiteTally& tally,
                          const std::vector<SuiteCaseResult>& results);

/// "<solver> solved N/M  local L  converged C  false claims F  contract violations V  median T ms".
std::string tally_line(const std::string& solver, const SuiteTally& tally);

/// One case in a line ("  <solver> <problem> from <start>: <termination>, cost ... (<outcome>)"),
/// with the broken contract when it is; empty when `verbose` is false and the contract holds,
/// or the start is not evaluable.
std::string case_line(const std::string& solver, const SuiteCaseResult& result, bool verbose);

}  // namespace kincal::problems
