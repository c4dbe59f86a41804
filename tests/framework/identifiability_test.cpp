// Identifiability figures on Jacobians with known singular values, named null-space
// combinations, and the covariance of a calibration against the spread over many seeds.

#include "kincal/framework/analysis/identifiability.hpp"

#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>

#include "kincal/framework/analysis/calibration_report.hpp"
#include "kincal/framework/analysis/identifiability_words.hpp"
#include "kincal/framework/base/random.hpp"
#include "kincal/framework/calibration/simulation.hpp"
#include "kincal/framework/least_squares/solver_registry.hpp"
#include "kincal/framework/least_squares/uncertainty.hpp"
#include "kincal/models/presets.hpp"

namespace kincal {
namespace {

// Every index against its formula on the singular values of the scaled Jacobian.
TEST(Identifiability, IndicesFollowTheirDefinitions) {
  // Columns e1, e2 and (e1 + 2 e3)/sqrt(5): unit norms, Gram matrix known.
  MatrixXd J = MatrixXd::Zero(4, 3);
  J(0, 0) = 1;
  J(1, 1) = 1;
  J(0, 2) = 1 / std::sqrt(5.0);
  J(2, 2) = 2 / std::sqrt(5.0);
  J *= 7.0;  // column scaling must remove this
  const Identifiability a = analyze_identifiability(J, {"a", "b", "c"});
  const Eigen::JacobiSVD<MatrixXd> svd(J / 7.0);
  const VectorXd s = svd.singularValues();
  ASSERT_EQ(a.singular_values.size(), 3);
  EXPECT_NEAR((a.singular_values - s).norm(), 0, 1e-12);
  EXPECT_EQ(a.rank, 3);
  EXPECT_EQ(a.numerical_rank, 3);
  EXPECT_NEAR(a.condition_number, s[0] / s[2], 1e-12);
  EXPECT_NEAR(a.o1, std::cbrt(s[0] * s[1] * s[2]) / 2.0, 1e-12);
  EXPECT_NEAR(a.o2, s[2] / s[0], 1e-12);
  EXPECT_NEAR(a.o3, s[2], 1e-12);
  EXPECT_NEAR(a.o4, s[2] * s[2] / s[0], 1e-12);
  EXPECT_NEAR(a.o5, 1 / (1 / (s[0] * s[0]) + 1 / (s[1] * s[1]) + 1 / (s[2] * s[2])), 1e-12);
  EXPECT_NEAR(a.column_norms[2], 7.0, 1e-12);
  EXPECT_FALSE(a.rank_deficient());
}

TEST(Identifiability, NamesTheCombinationThatCannotBeSeparated) {
  // Readings depend on offset_a + offset_b only (two encoder zeros in series), and not at
  // all on "ghost".
  Random rng(3);
  MatrixXd J(20, 4);
  for (int i = 0; i < 20; ++i) {
    J(i, 0) = rng.symmetric(1);
    J(i, 1) = 1;
    J(i, 2) = 2;  // offset_b in half-millimetres: same direction, different scale
    J(i, 3) = 0;
  }
  const Identifiability a = analyze_identifiability(J, {"x", "offset_a", "offset_b", "ghost"});
  EXPECT_EQ(a.rank, 2);
  EXPECT_EQ(a.numerical_rank, 2);
  EXPECT_TRUE(a.rank_deficient());
  EXPECT_TRUE(std::isinf(a.condition_number));
  EXPECT_EQ(a.o1, 0);
  EXPECT_EQ(a.unseen, std::vector<std::string>{"ghost"});
  ASSERT_EQ(a.combinations.size(), 1u);
  bool found = false;
  for (const auto& c : a.combinations) {
    EXPECT_TRUE(c.null_space);
    if (c.terms.size() == 2 && c.terms[0].first == "offset_a") {
      // In parameter units: d offset_a = -2 d offset_b leaves the readings unchanged.
      EXPECT_NEAR(c.terms[0].second, 2 / std::sqrt(5.0), 1e-9);
      EXPECT_EQ(c.terms[1].first, "offset_b");
      EXPECT_NEAR(c.terms[1].second, -1 / std::sqrt(5.0), 1e-9);
      EXPECT_EQ(c.describe(), "+0.894 offset_a -0.447 offset_b");
      found = true;
    }
  }
  EXPECT_TRUE(found);
  // Keeping x and one of the offsets is the identifiable subset.
  const auto keep = identifiable_subset(J);
  ASSERT_EQ(keep.size(), 2u);
  EXPECT_EQ(keep[0], 0);
  EXPECT_TRUE(keep[1] == 1 || keep[1] == 2);
}

// An exact dependency leaves s_n at rounding level (1e-17), not 0: the figures must not be
// ratios of that noise, and a weak but real direction just above the threshold must not be
// swallowed.
TEST(Identifiability, NumericallyRankDeficientGivesZeroIndicesAndInfiniteCondition) {
  Random rng(5);
  MatrixXd J(30, 3);
  for (int i = 0; i < 30; ++i) {
    J(i, 0) = rng.symmetric(1);
    J(i, 1) = rng.symmetric(1);
    J(i, 2) = 0.3 * J(i, 0) - 0.7 * J(i, 1);  // dependent, up to rounding
  }
  const Identifiability a = analyze_identifiability(J, {"a", "b", "c"});
  ASSERT_GT(a.singular_values[2], 0.0);  // the SVD leaves rounding noise
  EXPECT_LT(a.singular_values[2], a.numerical_threshold);
  EXPECT_EQ(a.numerical_rank, 2);
  EXPECT_TRUE(a.rank_deficient());
  EXPECT_TRUE(std::isinf(a.condition_number));
  for (const double index : {a.o1, a.o2, a.o3, a.o4, a.o5}) EXPECT_EQ(index, 0.0);
  EXPECT_TRUE(to_json(a)["condition_number"].is_null());
  EXPECT_NE(to_text(a).find("rank deficient: 2 of 3 directions determined"), std::string::npos)
      << to_text(a);

  // Perturbed to s_3 / s_1 ~ 1e-3, above rcond = 1e-6: full rank, finite figures.
  for (int i = 0; i < 30; ++i) J(i, 2) += 1e-3 * rng.symmetric(1);
  const Identifiability b = analyze_identifiability(J, {"a", "b", "c"});
  EXPECT_EQ(b.numerical_rank, 3);
  EXPECT_TRUE(std::isfinite(b.condition_number));
  EXPECT_GT(b.o3, 0.0);
  EXPECT_NEAR(b.o2, 1 / b.condition_number, 1e-15);
}

TEST(Identifiability, FewerResidualsThanParametersIsRankDeficient) {
  const MatrixXd J = MatrixXd::Random(3, 5);
  const Identifiability a = analyze_identifiability(J, {"a", "b", "c", "d", "e"});
  EXPECT_EQ(a.singular_values.size(), 5);
  EXPECT_EQ(a.numerical_rank, 3);
  EXPECT_EQ(std::count_if(a.combinations.begin(), a.combinations.end(),
                          [](const auto& c) { return c.null_space; }),
            2);
}

// Of two columns that duplicate each other (c1 = 2 c0, c3 = -c2 + 1e-12 noise) the one of the
// lower class is kept, whatever the columns' order and scale; what is fixed is named with
// what it duplicates, in parameter units; a rounding-noise column counts as unseen.
TEST(Identifiability, PrioritiesChooseAmongDuplicatesAndTheDroppedAreExplained) {
  MatrixXd J(6, 5);
  J << 1, 2, 0, 0, 0,     //
      0, 0, 1, -1, 0,     //
      2, 4, 0, 0, 1e-18,  //
      0, 0, 3, -3, 0,     //
      1, 2, 1, -1, 0,     //
      0, 0, 0, 0, 0;
  J(5, 3) = 1e-12;  // c3 is -c2 up to a direction far below the rank threshold
  const std::vector<std::string> names = {"a", "b", "c", "d", "noise"};
  EXPECT_EQ(identifiable_subset(J, {1, 0, 0, 1, 0}), (std::vector<int>{1, 2}));
  EXPECT_EQ(identifiable_subset(J, {0, 1, 1, 0, 0}), (std::vector<int>{0, 3}));
  EXPECT_EQ(identifiable_subset(J, std::vector<int>{}).size(), 2u);
  const auto dependent = dependent_parameters(J, names, {1, 2});
  ASSERT_EQ(dependent.size(), 3u);
  EXPECT_EQ(dependent[0].name, "a");
  ASSERT_EQ(dependent[0].equivalent.size(), 1u);
  EXPECT_EQ(dependent[0].equivalent[0].first, "b");
  EXPECT_NEAR(dependent[0].equivalent[0].second, 0.5, 1e-12);  // a moves the readings as b/2
  EXPECT_EQ(dependent[1].name, "d");
  EXPECT_NEAR(dependent[1].equivalent[0].second, -1.0, 1e-9);
  EXPECT_EQ(dependent[2].name, "noise");
  EXPECT_TRUE(dependent[2].unseen);
}

// Issue 37: the choice works on the triangular factor of J, so the rows' order and count
// cannot change it. Columns that duplicate each other exactly (as a URDF arm's first joint
// origin and the base frame do) differ only by rounding once factored, and rounding must not
// decide which is kept: of exact duplicates in one class, the first. Checked on a tall J
// (several of the factor's blocks) with its rows in two orders.
TEST(Identifiability, ExactDuplicatesKeepTheFirstWhateverTheRowsOrder) {
  Random rng(11);
  const int m = 3000;
  MatrixXd J(m, 6);
  for (Eigen::Index i = 0; i < J.size(); ++i) J.data()[i] = rng.symmetric(1.0);
  J.col(2) = J.col(0);         // an exact duplicate of column 0
  J.col(4) = -3.0 * J.col(1);  // a scaled one of column 1
  J.col(5) = J.col(3);
  std::vector<int> order(m);
  for (int i = 0; i < m; ++i) order[static_cast<std::size_t>(i)] = (i * 7919) % m;
  const MatrixXd shuffled = J(order, Eigen::all);
  const std::vector<int> expected = {0, 1, 3};
  for (const MatrixXd* matrix : {static_cast<const MatrixXd*>(&J), &shuffled}) {
    EXPECT_EQ(identifiable_subset(*matrix), expected);
    EXPECT_EQ(identifiable_subset(*matrix, {0, 0, 0, 0, 0, 0}), expected);
    // A lower class still wins over the first.
    EXPECT_EQ(identifiable_subset(*matrix, {1, 1, 0, 0, 0, 1}), (std::vector<int>{2, 3, 4}));
  }
  const std::vector<std::string> names = {"a", "b", "c", "d", "e", "f"};
  const auto dependent = dependent_parameters(shuffled, names, expected);
  ASSERT_EQ(dependent.size(), 3u);
  EXPECT_EQ(dependent[0].name, "c");
  EXPECT_NEAR(dependent[0].equivalent.at(0).second, 1.0, 1e-12);
  EXPECT_EQ(dependent[1].name, "e");
  EXPECT_NEAR(dependent[1].equivalent.at(0).second, -3.0, 1e-12);
}

// Issue 35, item A7: a motion of the whole setup that changes no fit but shows in J (a turn
// of a setup of sockets turns their residuals) is a direction the data cannot determine when
// the free parameters reproduce it; when they do not, the analyses are those without it.
TEST(Identifiability, TurnsTheParametersReproduceAreNotDetermined) {
  Random rng(7);
  const int m = 40;
  MatrixXd J(m, 4), turn(m, 1);
  for (int i = 0; i < m; ++i) {
    J(i, 0) = rng.symmetric(1);
    J(i, 1) = rng.symmetric(1);
    turn(i, 0) = 0.01 * rng.symmetric(1);  // small, as the residuals it turns
    J(i, 2) = 2 * J(i, 0) + turn(i, 0);    // c moves the readings as 2 a and the turn
    J(i, 3) = rng.symmetric(1);
  }
  const std::vector<std::string> names = {"a", "b", "c", "d"};
  const Identifiability without = analyze_identifiability(J, names);
  EXPECT_EQ(without.numerical_rank, 4);  // the turn looks like information
  const Identifiability a = analyze_identifiability(J, names, {}, turn);
  EXPECT_EQ(a.frame_turns, 1);
  EXPECT_EQ(a.numerical_rank, 3);
  EXPECT_TRUE(a.rank_deficient());
  EXPECT_EQ(identifiable_subset(J, {}, turn), (std::vector<int>{0, 1, 3}));
  EXPECT_EQ(identifiable_subset(J, std::vector<int>{0, 0, 0, 0}, {}, turn),
            (std::vector<int>{0, 1, 3}));
  const auto dependent = dependent_parameters(J, names, {0, 1, 3}, {}, turn);
  ASSERT_EQ(dependent.size(), 1u);
  EXPECT_EQ(dependent[0].name, "c");
  EXPECT_TRUE(dependent[0].turn);
  ASSERT_EQ(dependent[0].equivalent.size(), 1u);
  EXPECT_EQ(dependent[0].equivalent[0].first, "a");
  EXPECT_NEAR(dependent[0].equivalent[0].second, 2.0, 1e-9);
  // A prior on every parameter pins the turn; one on b and d only does not (it takes c - 2 a).
  Identifiability pinned = a;
  add_prior(pinned, J, VectorXd::Ones(4), VectorXd::Ones(4), {}, turn);
  EXPECT_EQ(pinned.numerical_rank_with_prior, 4);
  Identifiability unpinned = a;
  add_prior(unpinned, J, (VectorXd(4) << 0, 1, 0, 1).finished(), VectorXd::Ones(4), {}, turn);
  EXPECT_EQ(unpinned.numerical_rank_with_prior, 3);

  // A turn the parameters do not reproduce changes nothing, to the last bit.
  MatrixXd other(m, 1);
  for (int i = 0; i < m; ++i) other(i, 0) = rng.symmetric(1);
  const Identifiability b = analyze_identifiability(J, names, {}, other);
  EXPECT_EQ(b.frame_turns, 0);
  EXPECT_EQ(b.numerical_rank, 4);
  EXPECT_EQ(b.singular_values, without.singular_values);
  EXPECT_EQ(identifiable_subset(J, std::vector<int>{0, 0, 1, 1}, {}, other),
            identifiable_subset(J, std::vector<int>{0, 0, 1, 1}));
  // Nor does a turn of residuals that are all zero (it is no direction).
  EXPECT_EQ(analyze_identifiability(J, names, {}, MatrixXd::Zero(m, 3)).singular_values,
            without.singular_values);
}

// Parameters in words, as the table of fixed parameters shows them.
TEST(Identifiability, ParameterNamesInWords) {
  EXPECT_EQ(parameter_words("shoulder_pan_joint.origin.rx"),
            "shoulder_pan_joint's origin, rotation about x");
  EXPECT_EQ(parameter_words("leg1.platform.z"), "leg1's platform, shift along z");
  EXPECT_EQ(parameter_words("tracker.frame.y"), "tracker's frame, shift along y");
  EXPECT_EQ(parameter_words("elbow_joint.offset"), "elbow_joint's zero offset");
  EXPECT_EQ(parameter_words("base.rz"), "the base frame, rotation about z");
}

TEST(Uncertainty, SigmaHatUsesTheDegreesOfFreedom) {
  MatrixXd J(4, 1);
  J << 1, 1, 1, 1;
  VectorXd r(4);
  r << 1, -1, 1, -1;
  const ParameterUncertainty u = estimate_uncertainty(J, r);
  EXPECT_EQ(u.degrees_of_freedom, 3);
  EXPECT_NEAR(u.sigma, std::sqrt(4.0 / 3.0), 1e-12);
  EXPECT_NEAR(u.std[0], u.sigma / 2.0, 1e-12);  // mean of 4 readings
  EXPECT_NEAR(u.correlation(0, 0), 1.0, 1e-12);
  EXPECT_TRUE(std::isnan(estimate_uncertainty(J.topRows(1), r.head(1)).sigma));
}

// Issue 19, item 3: calibrate --allow-rank-deficient fixing every free parameter crashed in
// Eigen's SVD of a Jacobian without columns (exit 139). No parameter, no reading, or nothing
// any reading depends on: no crash, and never a std of 0 for what nothing determines.
TEST(Uncertainty, NoParameterOrNoInformationIsNaNNotACrashOrAStdOfZero) {
  const VectorXd r = VectorXd::Constant(5, 0.1);
  const ParameterUncertainty none = estimate_uncertainty(MatrixXd(5, 0), r);
  EXPECT_EQ(none.covariance.rows(), 0);
  EXPECT_EQ(none.std.size(), 0);
  EXPECT_EQ(none.correlation.size(), 0);
  EXPECT_EQ(estimate_posterior_uncertainty(MatrixXd(5, 0), r, VectorXd(0)).std.size(), 0);
  EXPECT_EQ(parameter_covariance(MatrixXd(5, 0), 1.0).size(), 0);
  EXPECT_TRUE(identifiable_subset(MatrixXd(5, 0)).empty());
  Identifiability a = analyze_identifiability(MatrixXd(5, 0), {});
  add_prior(a, MatrixXd(5, 0), VectorXd(0), VectorXd(0));
  EXPECT_EQ(a.numerical_rank_with_prior, 0);

  const ParameterUncertainty zero = estimate_uncertainty(MatrixXd::Zero(5, 2), r);
  for (int i = 0; i < 2; ++i) {
    EXPECT_TRUE(std::isnan(zero.std[i])) << i;
    EXPECT_TRUE(std::isnan(zero.correlation(i, 1 - i))) << i;
  }
  const Identifiability blind = analyze_identifiability(MatrixXd::Zero(5, 2), {"a", "b"});
  EXPECT_EQ(blind.numerical_rank, 0);
  EXPECT_EQ(blind.unseen.size(), 2u);
  const Identifiability no_rows = analyze_identifiability(MatrixXd(0, 2), {"a", "b"});
  EXPECT_EQ(no_rows.numerical_rank, 0);
  EXPECT_EQ(no_rows.unseen.size(), 2u);
  EXPECT_TRUE(std::isnan(parameter_covariance(MatrixXd(0, 2), 1.0)(0, 0)));

  // One parameter seen, one not: the first is determined, the second is not (NaN, not 0).
  MatrixXd J = MatrixXd::Zero(5, 2);
  J.col(0).setOnes();
  const ParameterUncertainty half = estimate_uncertainty(J, r + VectorXd::LinSpaced(5, 0, 1));
  EXPECT_GT(half.std[0], 0);
  EXPECT_TRUE(std::isfinite(half.std[0]));
  EXPECT_TRUE(std::isnan(half.std[1]));
  EXPECT_NEAR(half.correlation(0, 0), 1.0, 1e-12);
  EXPECT_TRUE(std::isnan(half.correlation(0, 1)));
}

// The reported standard deviations must describe the real scatter of the estimates: same
// truth and configurations, fresh gauge noise per seed, many solves.
TEST(Uncertainty, ReportedStdMatchesTheSpreadOverSeeds) {
  ScenarioOptions options;
  options.num_configurations = 60;
  options.noise_half_width.set(kincal::kMillimetre, 0.0);
  options.num_validation = 0;
  options.seed = 11;
  const Scenario exact = make_scenario(make_cube_hexapod(), options);
  const auto solver = SolverRegistry::global().create("gn");
  SolverOptions solver_options;
  // Small noise keeps the problem in its linear regime, where sigma^2 (J^T J)^-1 is exact.
  const double a = 1e-4, sigma = a / std::sqrt(3.0);
  const int trials = 300;
  const int n = static_cast<int>(exact.free_indices.size());
  MatrixXd estimates(trials, n);
  VectorXd mean_reported = VectorXd::Zero(n);
  double mean_sigma_hat = 0;
  Random rng(2024);
  for (int t = 0; t < trials; ++t) {
    Measurements data = exact.calibration;
    for (int j = 0; j < data.size(); ++j) data.readings(j, 0) += rng.symmetric(a);
    CalibrationProblem problem(exact.model, data, exact.nominal, exact.free_indices);
    VectorXd x = problem.initial_free_parameters();
    const Summary summary = solver->solve(problem, x, solver_options);
    ASSERT_TRUE(summary.converged()) << summary.message;
    const CalibrationReport report = make_calibration_report(problem, x, summary, {});
    estimates.row(t) = x.transpose();
    mean_reported += report.uncertainty.std / trials;
    mean_sigma_hat += report.uncertainty.sigma / trials;
  }
  EXPECT_NEAR(mean_sigma_hat, sigma, 0.05 * sigma);
  const VectorXd truth_free = [&] {
    VectorXd v(n);
    for (int i = 0; i < n; ++i) v[i] = exact.truth[exact.free_indices[i]];
    return v;
  }();
  for (int i = 0; i < n; ++i) {
    const VectorXd col = estimates.col(i);
    const double mean = col.mean();
    const double spread = std::sqrt((col.array() - mean).square().sum() / (trials - 1));
    // Sample std of 300 draws: relative standard error 1/sqrt(2 * 299) ~ 4%; allow 5 of them.
    EXPECT_NEAR(spread / mean_reported[i], 1.0, 0.2)
        << exact.model->parameters()[exact.free_indices[i]].name;
    // Unbiased: the mean lies within 4 standard errors of the truth.
    EXPECT_NEAR(mean, truth_free[i], 4 * spread / std::sqrt(double(trials)));
  }
}

}  // namespace
}  // namespace kincal
