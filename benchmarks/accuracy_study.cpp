// kincal-accuracy-study: accuracy and robustness of every registered backend on the paper's
// Table 2 cases and harder ones, against the Cramér-Rao bound. See docs/benchmarks.md.

#include <cstdio>
#include <cstdlib>
#include <fstream>
#include <iostream>
#include <sstream>
#include <stdexcept>
#include <string>

#include "benchmarks/study_report.hpp"

namespace {

using kincal::bench::StudyOptions;

const char* const kUsage =
    "usage: kincal-accuracy-study [options]\n"
    "  --trials N                 Monte Carlo seeds per case (default 200)\n"
    "  --seed S                   base seed; trial t uses derive_seed(S, t) (default 1)\n"
    "  --threads N                worker threads, 0 = all cores (default 0)\n"
    "  --validation N             validation poses per trial (default 50)\n"
    "  --cases LIST               comma-separated ids among 1,2,3,4,5,3e20,m300 (default all)\n"
    "  --solvers LIST             registry names (default: every featured backend)\n"
    "  --exclude LIST             featured backends to leave out of the default list\n"
    "  --track LIST               solvers with per-iteration validation errors on cases 1-5\n"
    "                             (default gn,lm)\n"
    "  --max-iterations N         iteration limit of gn, lm, ceres, ipopt (default 200)\n"
    "  --nlopt-evaluations N      evaluation limit of gradient-based NLopt (default 2000)\n"
    "  --nlopt-df-evaluations N   evaluation limit of derivative-free NLopt (default 10000)\n"
    "  --derivative-free-cases L  cases on which nlopt:LN_* run (default 1)\n"
    "  --nlopt-limited-cases L    cases on which nlopt:* run on fewer trials (default m300)\n"
    "  --limited-trials N         trials of those cells and of nlopt:LN_* (default 20)\n"
    "  --out DIR                  output directory (default accuracy-results)\n"
    "  --quiet                    no progress on stderr, no table on stdout\n";

std::vector<std::string> split(const std::string& text) {
  std::vector<std::string> items;
  std::stringstream in(text);
  for (std::string item; std::getline(in, item, ',');)
    if (!item.empty()) items.push_back(item);
  return items;
}

int to_int(const std::string& option, const std::string& value) {
  try {
    std::size_t used = 0;
    const int v = std::stoi(value, &used);
    if (used == value.size()) return v;
  } catch (const std::exception&) {
  }
  throw std::invalid_argument(option + ": expected an integer, got '" + value + "'");
}

}  // namespace

int main(int argc, char** argv) {
  StudyOptions options;
  std::string out_dir = "accuracy-results";
  bool quiet = false;
  try {
    for (int i = 1; i < argc; ++i) {
      const std::string arg = argv[i];
      if (arg == "--help" || arg == "-h") {
        std::fputs(kUsage, stdout);
        return 0;
      }
      if (arg == "--quiet") {
        quiet = true;
        continue;
      }
      if (i + 1 >= argc) throw std::invalid_argument(arg + ": missing value (see --help)");
      const std::string value = argv[++i];
      if (arg == "--trials") {
        options.trials = to_int(arg, value);
      } else if (arg == "--seed") {
        options.seed = static_cast<std::uint64_t>(std::stoull(value));
      } else if (arg == "--threads") {
        options.threads = to_int(arg, value);
      } else if (arg == "--validation") {
        options.validation = to_int(arg, value);
      } else if (arg == "--cases") {
        options.cases = split(value);
      } else if (arg == "--solvers") {
        options.solvers = split(value);
      } else if (arg == "--exclude") {
        options.excluded_solvers = split(value);
      } else if (arg == "--track") {
        options.tracked_solvers = split(value);
      } else if (arg == "--max-iterations") {
        options.max_iterations = to_int(arg, value);
      } else if (arg == "--nlopt-evaluations") {
        options.nlopt_gradient_evaluations = to_int(arg, value);
      } else if (arg == "--nlopt-df-evaluations") {
        options.nlopt_derivative_free_evaluations = to_int(arg, value);
      } else if (arg == "--derivative-free-cases") {
        options.derivative_free_cases = split(value);
      } else if (arg == "--nlopt-limited-cases") {
        options.nlopt_limited_cases = split(value);
      } else if (arg == "--limited-trials") {
        options.limited_trials = to_int(arg, value);
      } else if (arg == "--out") {
        out_dir = value;
      } else {
        throw std::invalid_argument("unknown option '" + arg + "' (see --help)");
      }
    }
    options.progress = !quiet;
    const auto results = kincal::bench::run_study(options);
    kincal::bench::write_study_files(results, out_dir);
    if (!quiet) {
      std::ifstream table(out_dir + "/accuracy.md");
      std::cout << table.rdbuf() << "\nresults in " << out_dir << "/\n";
    }
  } catch (const std::exception& e) {
    std::fprintf(stderr, "kincal-accuracy-study: %s\n", e.what());
    return 2;
  }
  return 0;
}
