#include "kincal/framework/analysis/starts_report.hpp"

#include <cstdio>

namespace kincal {

namespace {

std::string format_cost(double cost) {
  char text[32];
  std::snprintf(text, sizeof text, "%.6g", cost);
  return text;
}

}  // namespace

std::string starts_text(const StartsReport& report) {
  const MultiStartResult& m = report.result;
  const int count = static_cast<int>(m.starts.size());
  if (count <= 1) return "";
  std::string out = "starts: " + std::to_string(count) + " from " + report.spread_from + ", seed " +
                    std::to_string(report.seed) + ": ";
  if (m.minima.empty()) return out + "none reached a solution\n";
  out += std::to_string(m.minima.size()) +
         (m.minima.size() == 1 ? " minimum" : " distinct minima") + ", cost";
  for (std::size_t i = 0; i < m.minima.size() && i < 5; ++i)
    out += std::string(i ? "," : "") + " " + format_cost(m.minima[i].cost) + " (" +
           std::to_string(m.minima[i].starts.size()) + ")";
  if (m.minima.size() > 5) out += ", ...";
  if (m.unsolved) out += "; " + std::to_string(m.unsolved) + " reached no solution";
  out += "\n";
  if (m.best_start != 0) {
    const StartOutcome& first = m.starts[0];
    out += "  the model's values (start 0) end in a higher minimum" +
           (reached_solution(first.summary) ? " of cost " + format_cost(first.summary.final_cost)
                                            : std::string(" or none")) +
           "; continuing with the best, from start " + std::to_string(m.best_start) + "\n";
  }
  if (m.minima.size() > 1)
    out +=
        "  a lower cost is not a closer geometry: minima whose costs differ by about the noise "
        "fit the data equally well (docs/benchmarks.md, \"Local minima\")\n";
  if (m.minima.size() > 1 && m.minima[0].starts.size() == 1)
    out += "  only one start reached the best minimum: a lower one may exist (more --starts)\n";
  return out;
}

nlohmann::ordered_json starts_json(const StartsReport& report) {
  const MultiStartResult& m = report.result;
  nlohmann::ordered_json out;
  out["count"] = m.starts.size();
  out["seed"] = report.seed;
  out["spread_from"] = report.spread_from;
  out["spread_assumed"] = report.spread_assumed;
  out["best_start"] = m.best_start;
  out["unsolved"] = m.unsolved;
  const char* verdict = m.starts.size() <= 1  ? "single_start"
                        : m.minima.size() > 1 ? "several_minima"
                                              : "one_minimum";
  out["verdict"] = verdict;
  std::string note;
  if (m.starts.size() <= 1)
    note =
        "one start: a local minimum with residuals as small as the noise cannot be told "
        "from the global one (--starts N compares several)";
  else if (m.minima.size() > 1)
    note = std::to_string(m.minima.size()) +
           " distinct minima: the estimate is the lowest, which is not a closer geometry when the "
           "costs differ by about the noise";
  else if (m.minima.empty())
    note = "no start reached a solution";
  else
    note = "every start that reached a solution ended at the same minimum";
  out["note"] = note;
  nlohmann::ordered_json minima = nlohmann::ordered_json::array();
  for (const DistinctMinimum& d : m.minima)
    minima.push_back(
        {{"cost", d.cost}, {"starts", d.starts}, {"distance_to_best", d.distance_to_best}});
  out["minima"] = minima;
  return out;
}

}  // namespace kincal
