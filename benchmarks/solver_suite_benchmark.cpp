// kincal-solver-suite-benchmark: every featured backend (and a few documented variants) on the
// Moré-Garbow-Hillstrom suite, each solve checked against the honesty contract; and the
// derivative-free algorithms against the number of parameters. Writes, into --out:
//   suite.csv          one row per backend, problem and start
//   suite_table.md     the backend x suite table of docs/solvers.md
//   dimension.csv      scalable problems at n = 2..24: solved, evaluations (plot_solver_suite.py)
// See docs/solvers.md, "The test suite".

#include <algorithm>
#include <chrono>
#include <cstdio>
#include <filesystem>
#include <fstream>
#include <functional>
#include <iostream>
#include <sstream>
#include <string>
#include <vector>

#include "kincal/framework/least_squares/solver_registry.hpp"
#include "kincal/problems/mgh_definitions.hpp"
#include "kincal/problems/mgh_problems.hpp"
#include "kincal/problems/suite_runner.hpp"

namespace {

using namespace kincal;
using problems::SuiteCaseResult;

const char* const kUsage =
    "usage: kincal-solver-suite-benchmark [--out DIR] [--skip-dimension] [--quiet]\n"
    "  --out DIR          output directory (default solver-suite-results)\n"
    "  --skip-dimension   leave out the derivative-free-versus-n experiment\n"
    "  --quiet            no progress on stderr, no table on stdout\n";

// A row of the table: a backend with options on top of the suite's defaults.
struct Variant {
  std::string label;  // as the table shows it
  std::string solver;
  std::function<void(SolverOptions&)> configure;
};

std::vector<Variant> variants() {
  std::vector<Variant> out;
  for (const auto& name : SolverRegistry::global().featured_names()) {
    out.push_back({name, name, {}});
    if (name == "ceres")
      out.push_back(
          {"ceres (best: tolerances 2.2e-16, 1000 iterations)", "ceres", [](SolverOptions& o) {
             o.max_iterations = 1000;
             o.function_tolerance = o.parameter_tolerance = o.gradient_tolerance = 2.2e-16;
           }});
    if (name.rfind("nlopt:LD_", 0) == 0)
      out.push_back({name + " (scaling=none)", name,
                     [settings = SolverRegistry::global().create(name)->parse_settings(
                          {{"scaling", "none"}})](SolverOptions& o) { o.backend = settings; }});
  }
  return out;
}

std::string csv_text(std::string text) {
  for (char& c : text)
    if (c == '"') c = '\'';
  return "\"" + text + "\"";
}

std::string format(const char* pattern, double value) {
  char buffer[64];
  std::snprintf(buffer, sizeof buffer, pattern, value);
  return buffer;
}

// The derivative-free experiment: scalable zero-residual problems from x0 at growing n, with
// a generous fixed budget, for the derivative-free algorithms and three references.
struct DimensionRow {
  std::string solver, problem;
  int n = 0;
  bool solved = false;
  int evaluations = 0;  // residual evaluations made
  double seconds = 0;
};

std::vector<DimensionRow> dimension_experiment(const std::vector<std::string>& solvers,
                                               bool progress) {
  using namespace problems::mgh;
  const std::vector<std::pair<std::string, std::function<Problem(int)>>> families = {
      {"extended_rosenbrock", extended_rosenbrock},
      {"extended_powell_singular", extended_powell_singular},
      {"variably_dimensioned", variably_dimensioned},
      {"discrete_boundary_value", discrete_boundary_value},
      {"discrete_integral_equation", discrete_integral_equation},
      {"broyden_tridiagonal", broyden_tridiagonal},
      {"broyden_banded", broyden_banded},
      {"brown_almost_linear", brown_almost_linear}};
  std::vector<DimensionRow> rows;
  for (const auto& solver : solvers) {
    if (progress) std::fprintf(stderr, "dimension experiment: %s\n", solver.c_str());
    for (const auto& [family, make] : families) {
      for (int n : {2, 4, 8, 12, 16, 20, 24}) {
        Problem p;
        try {
          p = make(n);
        } catch (const std::invalid_argument&) {
          continue;  // e.g. extended Powell needs a multiple of 4
        }
        SolverOptions options;
        if (solver.rfind("nlopt", 0) == 0) options.max_iterations = 20000;
        VectorXd x = p->start();
        const auto begin = std::chrono::steady_clock::now();
        const Summary s = SolverRegistry::global().create(solver)->solve(*p, x, options);
        DimensionRow row;
        row.solver = solver;
        row.problem = family;
        row.n = n;
        row.seconds =
            std::chrono::duration<double>(std::chrono::steady_clock::now() - begin).count();
        row.solved = problems::reaches(p->cost(x), p->published_minimum());
        row.evaluations = s.residual_evaluations;
        rows.push_back(row);
      }
    }
  }
  return rows;
}

}  // namespace

int main(int argc, char** argv) {
  std::string out_dir = "solver-suite-results";
  bool quiet = false, dimension = true;
  for (int i = 1; i < argc; ++i) {
    const std::string arg = argv[i];
    if (arg == "--help" || arg == "-h") {
      std::fputs(kUsage, stdout);
      return 0;
    } else if (arg == "--quiet") {
      quiet = true;
    } else if (arg == "--skip-dimension") {
      dimension = false;
    } else if (arg == "--out" && i + 1 < argc) {
      out_dir = argv[++i];
    } else {
      std::fprintf(stderr, "kincal-solver-suite-benchmark: unknown option '%s' (see --help)\n",
                   arg.c_str());
      return 2;
    }
  }
  try {
    std::filesystem::create_directories(out_dir);
    std::ofstream csv(out_dir + "/suite.csv");
    csv << "backend,problem,n,start,evaluable,termination,outcome,published_minimum,final_cost,"
           "iterations,residual_evaluations,jacobian_evaluations,seconds,contract_ok,message\n";
    std::ostringstream table;
    table << "| backend | solved | published local minimum | `converged` | false `converged` "
             "claims | contract violations | median time (ms) |\n|---|---|---|---|---|---|---|\n";
    for (const Variant& v : variants()) {
      if (!quiet) std::fprintf(stderr, "suite: %s\n", v.label.c_str());
      const auto results = problems::run_suite(v.solver, problems::mgh_problems(), v.configure);
      for (const SuiteCaseResult& r : results) {
        csv << csv_text(v.label) << "," << r.problem << "," << r.num_parameters << "," << r.start
            << "," << r.evaluable << ",";
        if (r.evaluable)
          csv << to_string(r.summary.termination) << "," << problems::to_string(r.outcome) << ","
              << format("%.9g", r.published_minimum) << "," << format("%.9g", r.summary.final_cost)
              << "," << r.summary.iterations << "," << r.summary.residual_evaluations << ","
              << r.summary.jacobian_evaluations << "," << format("%.6g", r.seconds) << ","
              << r.contract.ok() << "," << csv_text(r.summary.message) << "\n";
        else
          csv << ",,,,,,,,," << csv_text(r.why_not_evaluable) << "\n";
      }
      const problems::SuiteTally t = problems::tally(results);
      table << "| " << v.label << " | " << t.solved << "/" << t.cases << " | " << t.published_local
            << " | " << t.converged << " | " << t.false_claims << " | " << t.violations << " | "
            << format("%.3g", 1e3 * t.median_seconds) << " |\n";
    }
    for (const auto& missing : SolverRegistry::global().unavailable())
      table << "| " << missing.name << " | skipped: " << missing.reason << " | | | | | |\n";
    std::ofstream(out_dir + "/suite_table.md") << table.str();

    if (dimension) {
      std::vector<std::string> solvers = {"lm"};
      for (const auto& name : SolverRegistry::global().featured_names())
        if (name.rfind("nlopt:LN_", 0) == 0 || name == "nlopt:LD_LBFGS" || name == "nlopt:LD_SLSQP")
          solvers.push_back(name);
      std::ofstream dim(out_dir + "/dimension.csv");
      dim << "backend,problem,n,solved,residual_evaluations,seconds\n";
      for (const auto& row : dimension_experiment(solvers, !quiet))
        dim << row.solver << "," << row.problem << "," << row.n << "," << row.solved << ","
            << row.evaluations << "," << format("%.6g", row.seconds) << "\n";
    }
    if (!quiet) std::cout << table.str() << "\nresults in " << out_dir << "/\n";
  } catch (const std::exception& e) {
    std::fprintf(stderr, "kincal-solver-suite-benchmark: %s\n", e.what());
    return 2;
  }
  return 0;
}
