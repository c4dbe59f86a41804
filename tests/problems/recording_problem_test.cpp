// RecordingProblem (problems/recording_problem.hpp), the conformance checker's view of a
// backend's evaluations: it must see the warm evaluations too, and pass the inner problem's
// warm starts on, so that a backend solves through it as it would solve the problem itself.

#include <gtest/gtest.h>

#include "kincal/problems/recording_problem.hpp"
#include "solvers/solver_fixtures.hpp"

namespace kincal {
namespace {

TEST(RecordingProblem, PassesWarmStartsOnAndRecordsWarmEvaluations) {
  const auto problem = testing::paper_scenario(5, 1).make_problem();
  const problems::RecordingProblem recording(*problem);
  const std::unique_ptr<WarmStart> warm = recording.make_warm_start();
  ASSERT_NE(warm, nullptr);  // the hexapod's: forward kinematics iterates
  const VectorXd x0 = problem->initial_free_parameters();
  VectorXd r;
  ASSERT_TRUE(recording.evaluate(x0, &r, nullptr, nullptr, 1, warm.get()));
  EXPECT_EQ(recording.complete_points(), 1);
  EXPECT_EQ(recording.block_evaluations(), problem->num_residual_blocks());
  EXPECT_DOUBLE_EQ(recording.best_cost(), 0.5 * r.squaredNorm());
  EXPECT_EQ(recording.best_point(), x0);
}

}  // namespace
}  // namespace kincal
