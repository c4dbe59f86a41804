#include "kincal/problems/suite_report.hpp"

#include <cstdio>
#include <sstream>

#include "kincal/framework/base/format_text.hpp"

namespace kincal::problems {

std::string problem_list_text(const std::vector<std::shared_ptr<const TestProblem>>& problems) {
  std::string out =
      format_text("%-40s %3s %3s  %-16s %s\n", "problem", "n", "m", "starts", "published minimum");
  for (const auto& p : problems) {
    std::string starts;
    for (const auto& s : suite_starts(*p))
      starts += (starts.empty() ? "" : ",") + s.label + (s.evaluable ? "" : "(!)");
    out += format_text("%-40s %3d %3d  %-16s %.6g\n", p->name().c_str(), p->num_parameters(),
                       p->num_residuals(), starts.c_str(), p->published_minimum());
  }
  return out +
         "(!) = not evaluable: the cost overflows there. Costs are 1/2 |r|^2, half the paper's "
         "f.\n";
}

nlohmann::json to_json(const SuiteCaseResult& r) {
  nlohmann::json j = {{"problem", r.problem},
                      {"start", r.start},
                      {"n", r.num_parameters},
                      {"published_minimum", r.published_minimum},
                      {"evaluable", r.evaluable}};
  if (!r.evaluable) {
    j["why_not_evaluable"] = r.why_not_evaluable;
    return j;
  }
  j["termination"] = to_string(r.summary.termination);
  j["message"] = r.summary.message;
  j["iterations"] = r.summary.iterations;
  j["residual_evaluations"] = r.summary.residual_evaluations;
  j["jacobian_evaluations"] = r.summary.jacobian_evaluations;
  j["initial_cost"] = r.summary.initial_cost;
  j["final_cost"] = r.summary.final_cost;
  j["outcome"] = to_string(r.outcome);
  j["seconds"] = r.seconds;
  j["contract"] = {{"ok", r.contract.ok()}, {"violations", r.contract.violations}};
  return j;
}

nlohmann::json suite_json(const std::string& solver, const SuiteTally& t,
                          const std::vector<SuiteCaseResult>& results) {
  nlohmann::json entry = {{"name", solver},
                          {"cases", t.cases},
                          {"solved", t.solved},
                          {"published_local", t.published_local},
                          {"converged", t.converged},
                          {"false_claims", t.false_claims},
                          {"contract_violations", t.violations},
                          {"median_seconds", t.median_seconds},
                          {"results", nlohmann::json::array()}};
  for (const auto& r : results) entry["results"].push_back(to_json(r));
  return entry;
}

std::string tally_line(const std::string& solver, const SuiteTally& t) {
  return format_text(
      "%-34s solved %3d/%d  local %2d  converged %3d  false claims %d  contract "
      "violations %d  median %.3g ms",
      solver.c_str(), t.solved, t.cases, t.published_local, t.converged, t.false_claims,
      t.violations, 1e3 * t.median_seconds);
}

std::string case_line(const std::string& solver, const SuiteCaseResult& r, bool verbose) {
  std::ostringstream line;
  if (verbose && r.evaluable)
    line << "  " << solver << " " << r.problem << " from " << r.start << ": "
         << to_string(r.summary.termination) << ", cost " << r.summary.final_cost << " ("
         << to_string(r.outcome) << ")"
         << (r.contract.ok() ? "" : " CONTRACT BROKEN: " + r.contract.report()) << "\n";
  else if (!r.contract.ok())
    line << "  " << solver << " " << r.problem << " from " << r.start
         << ": CONTRACT BROKEN: " << r.contract.report() << "\n";
  return line.str();
}

}  // namespace kincal::problems
