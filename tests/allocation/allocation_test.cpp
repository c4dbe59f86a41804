// Allocation counting: the inner loops of lm and of the identification problem's
// evaluation allocate nothing once warm. This binary replaces malloc, calloc and realloc to
// count; a sanitizer (AddressSanitizer) replaces them too, so the binary is not built under
// KINCAL_SANITIZE (tests/CMakeLists.txt registers a skipped test saying so instead).

#include <gtest/gtest.h>

#include <atomic>
#include <cstdlib>

#include "kincal/framework/calibration/implicit_calibration_problem.hpp"
#include "kincal/framework/calibration/simulation.hpp"
#include "kincal/framework/least_squares/solver_registry.hpp"
#include "kincal/models/serial_arm_presets.hpp"
#include "kincal/models/urdf_arm.hpp"
#include "models/autodiff_twins.hpp"
#include "solvers/solver_fixtures.hpp"

// Counts heap allocations so that a test can check that the iteration loop makes none. It
// counts at malloc, not operator new: Eigen's vectors and matrices allocate through malloc
// directly, and operator new ends there too. Memory still comes from glibc's allocator
// (__libc_malloc), so free and everything else are unchanged.
namespace {
std::atomic<long> g_allocations{0};
}  // namespace

extern "C" {
void* __libc_malloc(std::size_t size);
void* __libc_calloc(std::size_t count, std::size_t size);
void* __libc_realloc(void* p, std::size_t size);
void* malloc(std::size_t size) noexcept {
  g_allocations.fetch_add(1, std::memory_order_relaxed);
  return __libc_malloc(size);
}
void* calloc(std::size_t count, std::size_t size) noexcept {
  g_allocations.fetch_add(1, std::memory_order_relaxed);
  return __libc_calloc(count, size);
}
void* realloc(void* p, std::size_t size) noexcept {
  g_allocations.fetch_add(1, std::memory_order_relaxed);
  return __libc_realloc(p, size);
}
}

namespace kincal {
namespace {

using kincal::testing::ExponentialFit;
using kincal::testing::paper_scenario;

std::unique_ptr<Solver> lm() { return SolverRegistry::global().create("lm"); }

TEST(LevenbergMarquardt, TheIterationLoopDoesNotAllocate) {
  for (const char* linear_solver : {"cholesky", "qr"}) {
    ExponentialFit problem;
    VectorXd x(3);
    x << 1, 2, 0;
    SolverOptions options;
    options.backend = lm()->parse_settings({{"linear_solver", linear_solver}});
    options.loss = RobustLoss::parse("huber:0.5");
    long at_first_step = -1, at_last_step = -1;
    options.callback = [&](const IterationRecord& record, const VectorXd&) {
      if (record.iteration > 0 && at_first_step < 0) at_first_step = g_allocations.load();
      at_last_step = g_allocations.load();
      return CallbackAction::kContinue;
    };
    const Summary summary = lm()->solve(problem, x, options);
    ASSERT_GT(summary.trace.size(), 3u) << summary.brief_report();
    EXPECT_EQ(at_last_step, at_first_step) << linear_solver;
  }
}

TEST(LevenbergMarquardt, TheIterationLoopDoesNotAllocateOnTheHexapod) {
  const Scenario scenario = paper_scenario(5, 1);
  const auto problem = scenario.make_problem();
  VectorXd x = problem->initial_free_parameters();
  SolverOptions options;
  long at_first_step = -1, at_last_step = -1;
  options.callback = [&](const IterationRecord& record, const VectorXd&) {
    if (record.iteration > 0 && at_first_step < 0) at_first_step = g_allocations.load();
    at_last_step = g_allocations.load();
    return CallbackAction::kContinue;
  };
  const Summary summary = lm()->solve(*problem, x, options);
  ASSERT_GT(summary.trace.size(), 5u) << summary.brief_report();
  EXPECT_EQ(at_last_step, at_first_step);
}

// The same for lm on the implicit formulation (Schur complement): between its first and its
// last accepted iterate, nothing is allocated per configuration or per iteration.
TEST(LevenbergMarquardt, TheImplicitIterationLoopDoesNotAllocateOnTheHexapod) {
  const Scenario scenario = paper_scenario(5, 1);
  const auto problem = scenario.make_problem();
  const ImplicitCalibrationProblem implicit(problem);
  VectorXd x = problem->initial_free_parameters();
  SolverOptions options;
  long at_first_step = -1, at_last_step = -1;
  options.callback = [&](const IterationRecord& record, const VectorXd&) {
    if (record.iteration > 0 && at_first_step < 0) at_first_step = g_allocations.load();
    at_last_step = g_allocations.load();
    return CallbackAction::kContinue;
  };
  const Summary summary = lm()->solve_implicit(implicit, x, options);
  ASSERT_GT(summary.trace.size(), 5u) << summary.brief_report();
  EXPECT_EQ(at_last_step, at_first_step);
}

// Not lm's, but this binary counts allocations: evaluating residuals and the Jacobian of
// the identification problem allocates nothing once the outputs and scratch are sized.
TEST(CalibrationProblemEvaluation, AllocatesNothingOnceWarm) {
  const Scenario scenario = paper_scenario(5, 1);
  const auto problem = scenario.make_problem();
  const VectorXd x = problem->initial_free_parameters();
  VectorXd r;
  MatrixXd J;
  ASSERT_TRUE(problem->evaluate(x, &r, &J));
  const long before = g_allocations.load();
  ASSERT_TRUE(problem->evaluate(x, &r, &J));
  ASSERT_TRUE(problem->evaluate(x, &r, nullptr));
  EXPECT_EQ(g_allocations.load(), before);
  // With a warm start (forward kinematics from the last poses), once it is made.
  const std::unique_ptr<WarmStart> warm = problem->make_warm_start();
  ASSERT_TRUE(problem->evaluate(x, &r, &J, nullptr, 1, warm.get()));
  const long warm_before = g_allocations.load();
  ASSERT_TRUE(problem->evaluate(x, &r, &J, nullptr, 1, warm.get()));
  ASSERT_TRUE(problem->evaluate(x, &r, nullptr, nullptr, 1, warm.get()));
  EXPECT_EQ(g_allocations.load(), warm_before);
}

// Automatic derivatives (framework/kinematics/autodiff.hpp) on fixed-size dual numbers and
// per-thread scratch: the twins of the hexapod and gauge (case 5) and of the PUMA 560 allocate
// nothing per configuration either.
TEST(AutoDiffEvaluation, AllocatesNothingOnceWarm) {
  ScenarioOptions options;
  options.num_configurations = 20;
  options.num_validation = 0;
  Scenario puma = make_scenario(make_puma560(), options);
  puma.model = kincal::testing::autodiff_twin(*puma.model);
  Scenario hexapod = paper_scenario(5, 1);
  hexapod.model = kincal::testing::autodiff_twin(*hexapod.model);
  for (const Scenario* scenario : {&hexapod, &puma}) {
    const auto problem = scenario->make_problem();
    const VectorXd x = problem->initial_free_parameters();
    VectorXd r;
    MatrixXd J;
    ASSERT_TRUE(problem->evaluate(x, &r, &J));
    const long before = g_allocations.load();
    ASSERT_TRUE(problem->evaluate(x, &r, &J));
    ASSERT_TRUE(problem->evaluate(x, &r, nullptr));
    EXPECT_EQ(g_allocations.load(), before) << scenario->model->mechanism().type();
  }
}

// The hand-written serial arms (the chain walk of models/serial_chain.hpp: forward kinematics
// and J_pose_params) allocate nothing per configuration: the PUMA 560 (DH links), the UR5
// (DH and Hayati links) and the UR5 imported from its URDF.
TEST(SerialArmEvaluation, AllocatesNothingOnceWarm) {
  ScenarioOptions options;
  options.num_configurations = 20;
  options.num_validation = 0;
  // The UR5 from its URDF with joint compliance and a payload column too: the deflections
  // and their derivatives live in fixed-size scratch (models/compliant_chain.hpp).
  for (const auto& make : {make_puma560, make_ur5, make_ur5_urdf, make_ur5_urdf_compliance}) {
    const Scenario scenario = make_scenario(make(), options);
    const auto problem = scenario.make_problem();
    const VectorXd x = problem->initial_free_parameters();
    VectorXd r;
    MatrixXd J;
    ASSERT_TRUE(problem->evaluate(x, &r, &J));
    const long before = g_allocations.load();
    ASSERT_TRUE(problem->evaluate(x, &r, &J));
    ASSERT_TRUE(problem->evaluate(x, &r, nullptr));
    EXPECT_EQ(g_allocations.load(), before) << scenario.model->mechanism().type();
  }
}

}  // namespace
}  // namespace kincal
