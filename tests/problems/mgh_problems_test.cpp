// The Moré-Garbow-Hillstrom suite: analytic Jacobians against finite differences at every
// start, the published minimisers attaining the published costs, and the published values
// reached, which checks the formulas and the data against the paper.

#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <set>

#include "jacobian_check.hpp"
#include "kincal/framework/least_squares/solver_registry.hpp"
#include "kincal/problems/mgh_problems.hpp"
#include "kincal/problems/suite.hpp"

namespace kincal::problems {
namespace {

using ProblemPtr = std::shared_ptr<const TestProblem>;

std::string test_name(const ::testing::TestParamInfo<ProblemPtr>& info) {
  return info.param->name();
}

VectorXd to_vector(const std::vector<double>& v) {
  return Eigen::Map<const VectorXd>(v.data(), static_cast<Eigen::Index>(v.size()));
}

// Residuals and Jacobian at x; fails the test when they cannot be computed.
void evaluate(const TestProblem& problem, const VectorXd& x, VectorXd& r, MatrixXd* J) {
  std::string why;
  ASSERT_TRUE(problem.evaluate(x, &r, J, &why)) << problem.name() << ": " << why;
}

class MghProblem : public ::testing::TestWithParam<ProblemPtr> {};

TEST_P(MghProblem, IsWellFormed) {
  const TestProblem& p = *GetParam();
  EXPECT_EQ(p.start().size(), p.num_parameters());
  EXPECT_GE(p.num_residuals(), p.num_parameters()) << "MGH problems have m >= n";
  ASSERT_FALSE(p.minima().empty());
  EXPECT_TRUE(p.minima().front().global);
  for (const auto& minimum : p.minima()) {
    EXPECT_GE(minimum.cost, p.published_minimum()) << "the global minimum comes first";
    if (!minimum.x.empty()) {
      EXPECT_EQ(static_cast<int>(minimum.x.size()), p.num_parameters());
    }
  }
  EXPECT_GE(p.number(), 1);
  EXPECT_LE(p.number(), 35);
}

// Central differences with a step relative to each coordinate, compared row by row against
// the row's largest entry (the 100 x0 starts have residuals up to 1e26).
TEST_P(MghProblem, AnalyticJacobianMatchesFiniteDifferences) {
  const TestProblem& p = *GetParam();
  std::vector<VectorXd> points;
  for (const SuiteStart& start : suite_starts(p))
    if (start.evaluable) points.push_back(start.x);
  for (const auto& minimum : p.minima())
    if (!minimum.x.empty()) points.push_back(to_vector(minimum.x));
  for (const VectorXd& x : points) {
    VectorXd r;
    MatrixXd J;
    evaluate(p, x, r, &J);
    const VectorXd step = (1e-6 * x.cwiseAbs().array().max(1.0)).matrix();
    auto f = [&](const VectorXd& z) {
      VectorXd rz;
      evaluate(p, x + step.cwiseProduct(z), rz, nullptr);
      return rz;
    };
    const MatrixXd numeric = kincal::testing::numerical_jacobian(f, VectorXd::Zero(x.size()), 1.0) *
                             step.cwiseInverse().asDiagonal();
    // The scale also covers the rounding of the differences, ~eps |r_i| / h: at Brown's
    // badly scaled start r_1 = x1 - 1e6 is 1e6 with a derivative of 1.
    const VectorXd row_scale =
        (1.0 + numeric.rowwise().lpNorm<Eigen::Infinity>().array() + 1e-3 * r.array().abs())
            .matrix();
    EXPECT_TRUE(kincal::testing::jacobians_match(row_scale.cwiseInverse().asDiagonal() * J,
                                                 row_scale.cwiseInverse().asDiagonal() * numeric,
                                                 1e-6))
        << p.name() << " at x = " << x.transpose();
  }
}

TEST_P(MghProblem, PublishedMinimisersAttainThePublishedCosts) {
  const TestProblem& p = *GetParam();
  for (const auto& minimum : p.minima()) {
    if (minimum.x.empty()) continue;
    VectorXd x = to_vector(minimum.x);
    if (!minimum.x_is_exact) {
      // The paper prints these to 4 digits: polish with lm, then check that the polished
      // point rounds to the printed one.
      SolverOptions options;
      options.max_iterations = 500;
      options.gradient_tolerance = 0;
      options.function_tolerance = 1e-16;
      options.parameter_tolerance = 1e-15;
      SolverRegistry::global().create("lm")->solve(p, x, options);
      for (int j = 0; j < x.size(); ++j)
        EXPECT_NEAR(x[j], minimum.x[j], 1e-3 * std::abs(minimum.x[j]))
            << p.name() << " coordinate " << j << ": the polished minimiser left the printed one";
    }
    const double cost = p.cost(x);
    if (minimum.cost == 0) {
      EXPECT_LT(cost, 1e-20) << p.name() << " " << minimum.where;
    } else if (minimum.x_is_exact) {
      EXPECT_NEAR(cost, minimum.cost, 1e-12 * minimum.cost) << p.name() << " " << minimum.where;
    } else {
      EXPECT_NEAR(cost, minimum.cost, 1e-5 * minimum.cost) << p.name() << " " << minimum.where;
    }
  }
}

// Where the paper gives the lowest value without a minimiser, lm (tight tolerances, generous
// budget) reaches it, to the 6 printed digits, from the best of the three starts. This is
// what checks the data tables and the formulas of those problems.
class MghMinimumWithoutMinimiser : public MghProblem {};

TEST_P(MghMinimumWithoutMinimiser, IsReachedFromAStandardStart) {
  const TestProblem& p = *GetParam();
  SolverOptions options;
  options.max_iterations = 5000;
  options.gradient_tolerance = 0;
  options.function_tolerance = 1e-15;
  options.parameter_tolerance = 1e-15;
  double best = std::numeric_limits<double>::infinity();
  for (const SuiteStart& start : suite_starts(p)) {
    if (!start.evaluable) continue;
    VectorXd x = start.x;
    const Summary summary = SolverRegistry::global().create("lm")->solve(p, x, options);
    best = std::min(best, summary.final_cost);
  }
  const double published = p.published_minimum();
  if (published == 0) {
    EXPECT_LT(best, 1e-20) << p.name();
  } else {
    EXPECT_NEAR(best, published, 1e-5 * published) << p.name();
  }
}

INSTANTIATE_TEST_SUITE_P(Suite, MghProblem, ::testing::ValuesIn(mgh_problems()), test_name);

std::vector<ProblemPtr> problems_without_minimiser() {
  std::vector<ProblemPtr> selected;
  for (const auto& p : mgh_problems())
    if (p->minima().front().x.empty()) selected.push_back(p);
  return selected;
}

INSTANTIATE_TEST_SUITE_P(Suite, MghMinimumWithoutMinimiser,
                         ::testing::ValuesIn(problems_without_minimiser()), test_name);

TEST(MghSuite, HasAllThirtyFiveProblemsWithUniqueNames) {
  std::set<int> numbers;
  std::set<std::string> names;
  for (const auto& p : mgh_problems()) {
    numbers.insert(p->number());
    EXPECT_TRUE(names.insert(p->name()).second) << p->name() << " twice";
  }
  EXPECT_EQ(numbers.size(), 35u);
  EXPECT_EQ(*numbers.begin(), 1);
  EXPECT_EQ(*numbers.rbegin(), 35);
}

// A pattern of many stars selects what one star selects. The suite's own recursive matcher was
// exponential in the stars: fuzz_cli_options stopped on `--problem '**...**ros\x9e'` after
// 12 s; the selection now uses the framework's linear glob_match.
TEST(MghSuite, ManyStarsSelectWhatOneStarSelects) {
  const std::string many(40, '*');
  const auto one = select_problems("*ros*"), lots = select_problems(many + "ros" + many);
  ASSERT_FALSE(one.empty());
  ASSERT_EQ(lots.size(), one.size());
  for (std::size_t i = 0; i < one.size(); ++i) EXPECT_EQ(lots[i]->name(), one[i]->name());
  EXPECT_THROW(select_problems(many + "ros" + many + "\x9e"), std::invalid_argument);
}

// Only the start whose cost overflows double precision is left out, and it is named.
TEST(MghSuite, OnlyTheOverflowingStartIsNotEvaluable) {
  std::vector<std::string> not_evaluable;
  for (const auto& p : mgh_problems())
    for (const SuiteStart& start : suite_starts(*p))
      if (!start.evaluable) {
        not_evaluable.push_back(p->name() + "@" + start.label);
        EXPECT_NE(start.why_not_evaluable.find("overflow"), std::string::npos)
            << start.why_not_evaluable;
      }
  EXPECT_EQ(not_evaluable, std::vector<std::string>{"mgh06_jennrich_sampson@100x0"});
}

TEST(MghSuite, StartsAreTheStandardOnesScaled) {
  const auto watson = select_problems("mgh20_watson_n6");
  ASSERT_EQ(watson.size(), 1u);
  // x0 = 0 scales to itself: one start, not three copies of it.
  EXPECT_EQ(suite_starts(*watson[0]).size(), 1u);
  const auto bard = select_problems("bard");
  ASSERT_EQ(bard.size(), 1u);
  const auto starts = suite_starts(*bard[0]);
  ASSERT_EQ(starts.size(), 3u);
  EXPECT_EQ(starts[0].label, "x0");
  EXPECT_EQ(starts[1].label, "10x0");
  EXPECT_EQ(starts[2].label, "100x0");
  EXPECT_EQ(starts[2].x, 100 * bard[0]->start());
}

// Bard's published local minimum lies at infinity (x2, x3 -> -inf): there the model tends to
// the constant x1, whose best value is the mean of the data.
TEST(MghSuite, BardsAsymptoticMinimumIsTheDataVariance) {
  const auto bard = select_problems("mgh08_bard")[0];
  VectorXd r;
  ASSERT_TRUE(bard->evaluate(Eigen::Vector3d(0, -1e15, -1e15), &r, nullptr));
  const double mean = r.mean();  // r = y - x1 - (vanishing) with x1 = 0
  const double cost = bard->cost(Eigen::Vector3d(mean, -1e15, -1e15));
  EXPECT_NEAR(cost, bard->minima()[1].cost, 1e-5 * bard->minima()[1].cost);
}

TEST(MghSuite, SelectsByGlobOrSubstringAndRejectsWhatMatchesNothing) {
  EXPECT_EQ(select_problems("watson").size(), 3u);
  EXPECT_EQ(select_problems("mgh2?_penalty_*").size(), 4u);
  EXPECT_EQ(select_problems("*").size(), mgh_problems().size());
  EXPECT_THROW(select_problems("no_such_problem"), std::invalid_argument);
}

}  // namespace
}  // namespace kincal::problems
