#include "kincal/problems/mgh_problems.hpp"

#include <stdexcept>

#include "kincal/framework/kinematics/parameters.hpp"  // glob_match, linear in the pattern
#include "kincal/problems/mgh_definitions.hpp"

namespace kincal::problems {
namespace {

// Sizes: the paper's own for fixed-size problems; for the others the sizes at which it
// publishes a minimum value (Watson n = 6, 9, 12; penalty I and II n = 4, 10; Chebyquad
// n = 8, 9, 10; Jennrich-Sampson m = 10; Brown-Dennis m = 20; Biggs m = 13), and where the
// minimum is zero (or closed-form) for every size, the sizes of MINPACK-1's test set
// (linear functions n = 5, m = 10; Box m = 10) or of CUTEst (Gulf m = 99), and n = 10 for
// the scalable problems 21-31 (12 for extended Powell, which needs a multiple of 4).
std::vector<std::shared_ptr<const TestProblem>> build() {
  using namespace mgh;
  return {rosenbrock(),
          freudenstein_roth(),
          powell_badly_scaled(),
          brown_badly_scaled(),
          beale(),
          jennrich_sampson(10),
          helical_valley(),
          bard(),
          gaussian(),
          meyer(),
          gulf(99),
          box_3d(10),
          powell_singular(),
          wood(),
          kowalik_osborne(),
          brown_dennis(20),
          osborne_1(),
          biggs_exp6(13),
          osborne_2(),
          watson(6),
          watson(9),
          watson(12),
          extended_rosenbrock(10),
          extended_powell_singular(12),
          penalty_1(4),
          penalty_1(10),
          penalty_2(4),
          penalty_2(10),
          variably_dimensioned(10),
          trigonometric(10),
          brown_almost_linear(10),
          discrete_boundary_value(10),
          discrete_integral_equation(10),
          broyden_tridiagonal(10),
          broyden_banded(10),
          linear_full_rank(5, 10),
          linear_rank_1(5, 10),
          linear_rank_1_zero_columns(5, 10),
          chebyquad(8),
          chebyquad(9),
          chebyquad(10)};
}

}  // namespace

const std::vector<std::shared_ptr<const TestProblem>>& mgh_problems() {
  static const std::vector<std::shared_ptr<const TestProblem>> problems = build();
  return problems;
}

std::vector<std::shared_ptr<const TestProblem>> select_problems(const std::string& pattern) {
  const bool wildcard = pattern.find_first_of("*?") != std::string::npos;
  std::vector<std::shared_ptr<const TestProblem>> selected;
  for (const auto& problem : mgh_problems()) {
    const bool match = wildcard ? glob_match(pattern, problem->name())
                                : problem->name().find(pattern) != std::string::npos;
    if (match) selected.push_back(problem);
  }
  if (selected.empty())
    throw std::invalid_argument("no suite problem matches '" + pattern +
                                "' (names look like mgh20_watson_n9; see kincal solver-suite "
                                "--list)");
  return selected;
}

}  // namespace kincal::problems
