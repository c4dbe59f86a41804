#pragma once
// The Moré-Garbow-Hillstrom problems one by one (J. J. Moré, B. S. Garbow, K. E. Hillstrom,
// "Testing unconstrained optimization software", ACM TOMS 7(1):17-41, 1981), written from the
// paper's formulas. Grouped by theme in mgh_small.cpp, mgh_data_fitting.cpp,
// mgh_scalable.cpp and mgh_linear.cpp; problems/mgh_problems.cpp chooses the sizes.
// Published values are converted to kincal's cost 1/2 |r|^2 (half the paper's f).

#include <initializer_list>
#include <memory>

#include "kincal/problems/formula_problem.hpp"

namespace kincal::problems::mgh {

using Problem = std::shared_ptr<const TestProblem>;

inline VectorXd vec(std::initializer_list<double> values) {
  VectorXd v(static_cast<Eigen::Index>(values.size()));
  Eigen::Index i = 0;
  for (double value : values) v[i++] = value;
  return v;
}

// Fixed-size problems with few parameters (mgh_small.cpp).
Problem rosenbrock();           // 1: n = 2, m = 2
Problem freudenstein_roth();    // 2: n = 2, m = 2
Problem powell_badly_scaled();  // 3: n = 2, m = 2
Problem brown_badly_scaled();   // 4: n = 2, m = 3
Problem beale();                // 5: n = 2, m = 3
Problem helical_valley();       // 7: n = 3, m = 3
Problem powell_singular();      // 13: n = 4, m = 4
Problem wood();                 // 14: n = 4, m = 6

// Data fitting (mgh_data_fitting.cpp).
Problem jennrich_sampson(int m);  // 6: n = 2; published minimum for m = 10
Problem bard();                   // 8: n = 3, m = 15
Problem gaussian();               // 9: n = 3, m = 15
Problem meyer();                  // 10: n = 3, m = 16
Problem gulf(int m);              // 11: n = 3, 3 <= m <= 100
Problem box_3d(int m);            // 12: n = 3, m >= 3
Problem kowalik_osborne();        // 15: n = 4, m = 11
Problem brown_dennis(int m);      // 16: n = 4; published minimum for m = 20
Problem osborne_1();              // 17: n = 5, m = 33
Problem biggs_exp6(int m);        // 18: n = 6; published minimum for m = 13
Problem osborne_2();              // 19: n = 11, m = 65

// Problems of any size (mgh_scalable.cpp). Published minima exist for the sizes noted; the
// functions throw std::invalid_argument for sizes whose minimum the paper does not give.
Problem watson(int n);                      // 20: m = 31; n = 6, 9, 12
Problem extended_rosenbrock(int n);         // 21: n even, m = n
Problem extended_powell_singular(int n);    // 22: n multiple of 4, m = n
Problem penalty_1(int n);                   // 23: m = n + 1; n = 4, 10
Problem penalty_2(int n);                   // 24: m = 2n; n = 4, 10
Problem variably_dimensioned(int n);        // 25: m = n + 2
Problem trigonometric(int n);               // 26: m = n
Problem brown_almost_linear(int n);         // 27: m = n
Problem discrete_boundary_value(int n);     // 28: m = n
Problem discrete_integral_equation(int n);  // 29: m = n
Problem broyden_tridiagonal(int n);         // 30: m = n
Problem broyden_banded(int n);              // 31: m = n
Problem chebyquad(int n);                   // 35: m = n; n = 1..10

// Linear functions (mgh_linear.cpp): closed-form minima for every n <= m.
Problem linear_full_rank(int n, int m);            // 32
Problem linear_rank_1(int n, int m);               // 33
Problem linear_rank_1_zero_columns(int n, int m);  // 34

}  // namespace kincal::problems::mgh
