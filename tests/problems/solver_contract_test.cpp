// The contract checker catches what it is there to catch: each rule broken on purpose by a
// fake backend, and an honest stop passed.

#include <gtest/gtest.h>

#include <cmath>

#include "kincal/framework/least_squares/solver_registry.hpp"
#include "kincal/problems/mgh_problems.hpp"
#include "kincal/problems/solver_contract.hpp"
#include "kincal/problems/suite.hpp"

namespace kincal::problems {
namespace {

std::shared_ptr<const TestProblem> problem(const std::string& name) {
  return select_problems(name).at(0);
}

VectorXd start(const TestProblem& p, const std::string& label) {
  for (const auto& s : suite_starts(p))
    if (s.label == label) return s.x;
  throw std::logic_error("no start " + label);
}

// A backend that does what `act` says: evaluates where it likes, returns what it likes, and
// reports what it likes.
class FakeSolver final : public Solver {
 public:
  using Act = std::function<Summary(const LeastSquaresProblem&, VectorXd&)>;
  explicit FakeSolver(Act act) : act_(std::move(act)) {}
  std::string name() const override { return "fake"; }
  Summary solve(const LeastSquaresProblem& p, VectorXd& x, const SolverOptions&) const override {
    return act_(p, x);
  }

 private:
  Act act_;
};

Summary report(const LeastSquaresProblem& p, const VectorXd& start, const VectorXd& x,
               TerminationType type, const std::string& message) {
  Summary s;
  s.termination = type;
  s.message = message;
  s.initial_cost = p.cost(start);
  s.final_cost = p.cost(x);
  return s;
}

bool mentions(const ContractCheck& check, const std::string& words) {
  return check.report().find(words) != std::string::npos;
}

TEST(SolverContract, AGradientClaimAtAPointWhereTheGradientIsLargeIsCaught) {
  // gn's old fault: the test fired at a later iterate, the unmoved start was returned.
  const auto rosenbrock = problem("mgh01_rosenbrock");
  const VectorXd x0 = rosenbrock->start();
  const FakeSolver liar([&](const LeastSquaresProblem& p, VectorXd& x) {
    return report(p, x0, x, TerminationType::kConverged, "gradient max-norm below tolerance");
  });
  const CheckedSolve run = solve_and_check(liar, *rosenbrock, x0, SolverOptions{});
  EXPECT_FALSE(run.contract.ok());
  EXPECT_TRUE(mentions(run.contract, "claims the gradient test")) << run.contract.report();
}

TEST(SolverContract, AnyOtherClaimNeedsAStationaryPoint) {
  const auto bard = problem("mgh08_bard");
  const FakeSolver liar([&](const LeastSquaresProblem& p, VectorXd& x) {
    return report(p, bard->start(), x, TerminationType::kConverged,
                  "relative cost change below tolerance");
  });
  const CheckedSolve run = solve_and_check(liar, *bard, bard->start(), SolverOptions{});
  EXPECT_TRUE(mentions(run.contract, "passes none of the three tests")) << run.contract.report();
}

TEST(SolverContract, AReturnedPointCostlierThanTheStartOrTheBestIsCaught) {
  // ipopt's old fault: failed, returning a point far uphill of everything it had seen.
  const auto beale = problem("mgh05_beale");
  const VectorXd x0 = beale->start();
  const FakeSolver uphill([&](const LeastSquaresProblem& p, VectorXd& x) {
    x = Eigen::Vector2d(3, 0.5);  // the minimiser: evaluated, then walked away from
    p.cost(x);
    x = Eigen::Vector2d(-5, 5);
    return report(p, x0, x, TerminationType::kFailed, "gave up");
  });
  const CheckedSolve run = solve_and_check(uphill, *beale, x0, SolverOptions{});
  EXPECT_TRUE(mentions(run.contract, "more than the start")) << run.contract.report();
  EXPECT_TRUE(mentions(run.contract, "evaluated a point that costs")) << run.contract.report();
}

TEST(SolverContract, AFinalCostThatIsNotTheCostAtXIsCaught) {
  const auto wood = problem("mgh14_wood");
  const FakeSolver misreport([&](const LeastSquaresProblem& p, VectorXd& x) {
    Summary s = report(p, wood->start(), x, TerminationType::kMaxIterations, "reached the limit");
    s.final_cost *= 0.5;
    return s;
  });
  const CheckedSolve run = solve_and_check(misreport, *wood, wood->start(), SolverOptions{});
  EXPECT_TRUE(mentions(run.contract, "is not the cost at x")) << run.contract.report();
}

TEST(SolverContract, ConvergenceOnAPlateauIsCaught) {
  // Gulf from 100 x0: every exponential underflows, the Jacobian is exactly zero there.
  const auto gulf = problem("mgh11_gulf");
  const VectorXd x0 = start(*gulf, "100x0");
  const FakeSolver fooled([&](const LeastSquaresProblem& p, VectorXd& x) {
    return report(p, x0, x, TerminationType::kConverged, "gradient max-norm below tolerance");
  });
  const CheckedSolve run = solve_and_check(fooled, *gulf, x0, SolverOptions{});
  EXPECT_TRUE(mentions(run.contract, "converged on a plateau")) << run.contract.report();
}

TEST(SolverContract, APartialPlateauMustBeNamed) {
  // Osborne 2 from 10 x0: lm converges in the two live parameters; the message names the
  // other nine. Drop that from the message and the checker objects.
  const auto osborne = problem("mgh19_osborne_2");
  const VectorXd x0 = start(*osborne, "10x0");
  const auto lm = SolverRegistry::global().create("lm");
  const FakeSolver silent([&](const LeastSquaresProblem& p, VectorXd& x) {
    Summary s = lm->solve(p, x, SolverOptions{});
    s.message = s.message.substr(0, s.message.find("; on a plateau"));
    return s;
  });
  const CheckedSolve honest = solve_and_check(*lm, *osborne, x0, SolverOptions{});
  EXPECT_TRUE(honest.contract.ok()) << honest.contract.report();
  EXPECT_TRUE(honest.summary.converged()) << honest.summary.brief_report();
  EXPECT_EQ(honest.contract.at_x.dead_parameters.size(), 9u);
  const CheckedSolve run = solve_and_check(silent, *osborne, x0, SolverOptions{});
  EXPECT_TRUE(mentions(run.contract, "does not name the plateau")) << run.contract.report();
}

TEST(SolverContract, HonestStopsPass) {
  const auto rosenbrock = problem("mgh01_rosenbrock");
  const VectorXd x0 = rosenbrock->start();
  const FakeSolver idle([&](const LeastSquaresProblem& p, VectorXd& x) {
    return report(p, x0, x, TerminationType::kMaxIterations, "reached max_iterations");
  });
  EXPECT_TRUE(solve_and_check(idle, *rosenbrock, x0, SolverOptions{}).contract.ok());
  const auto lm = SolverRegistry::global().create("lm");
  const CheckedSolve run = solve_and_check(*lm, *rosenbrock, x0, SolverOptions{});
  EXPECT_TRUE(run.summary.converged()) << run.summary.brief_report();
  EXPECT_TRUE(run.contract.ok()) << run.contract.report();
  EXPECT_GT(run.contract.start_cost, run.contract.cost_at_x);
}

TEST(SolverContract, AnUncomputableStartMustEndFailedWithXUntouched) {
  // Jennrich-Sampson's cost overflows at 100 x0.
  const auto js = problem("mgh06_jennrich_sampson");
  const VectorXd x0 = start(*js, "100x0");
  const FakeSolver pretends([&](const LeastSquaresProblem&, VectorXd& x) {
    x.setZero();
    Summary s;
    s.termination = TerminationType::kConverged;
    s.message = "gradient max-norm below tolerance";
    return s;
  });
  const CheckedSolve run = solve_and_check(pretends, *js, x0, SolverOptions{});
  EXPECT_FALSE(run.contract.start_computable);
  EXPECT_TRUE(mentions(run.contract, "the start is not computable, yet the termination"));
  EXPECT_TRUE(mentions(run.contract, "x was changed"));
}

// y = a t at four points, whose Jacobian is NaN where a > `fence` (everywhere by default): a
// model whose derivative divides by zero there.
class NanJacobianLine final : public LeastSquaresProblem {
 public:
  explicit NanJacobianLine(double fence = -HUGE_VAL) : fence_(fence) {}
  int num_parameters() const override { return 1; }
  int num_residual_blocks() const override { return 4; }
  int residuals_per_block() const override { return 1; }
  bool evaluate_block(int block, const VectorXd& x, Eigen::Ref<VectorXd> residuals,
                      Eigen::Ref<MatrixXd>* jacobian, std::string*) const override {
    residuals[0] = x[0] * block - 2.0 * block;
    if (jacobian) (*jacobian)(0, 0) = x[0] > fence_ ? std::nan("") : block;
    return true;
  }

 private:
  double fence_;
};

TEST(SolverContract, ANonFiniteStartMustEndFailedSayingSo) {
  const NanJacobianLine line;
  const VectorXd x0 = VectorXd::Constant(1, 1.0);
  const FakeSolver fooled([&](const LeastSquaresProblem& p, VectorXd& x) {
    return report(p, x0, x, TerminationType::kConverged, "gradient below tolerance");
  });
  const CheckedSolve run = solve_and_check(fooled, line, x0, SolverOptions{});
  EXPECT_FALSE(run.contract.start_finite);
  EXPECT_TRUE(mentions(run.contract, "not finite, yet the termination is converged"))
      << run.contract.report();
  const FakeSolver honest([&](const LeastSquaresProblem&, VectorXd&) {
    Summary s;
    s.termination = TerminationType::kFailed;
    s.message = "the Jacobian at the start has a non-finite entry (residual 1, parameter x0: nan)";
    return s;
  });
  EXPECT_TRUE(solve_and_check(honest, line, x0, SolverOptions{}).contract.ok());
}

TEST(SolverContract, ConvergenceWhereTheJacobianIsNotFiniteIsCaught) {
  // The minimum (a = 2) lies where the Jacobian is NaN.
  const NanJacobianLine line(1.5);
  const VectorXd x0 = VectorXd::Constant(1, 1.0);
  const FakeSolver fooled([&](const LeastSquaresProblem& p, VectorXd& x) {
    x[0] = 2;
    return report(p, x0, x, TerminationType::kConverged, "relative cost change below tolerance");
  });
  const CheckedSolve run = solve_and_check(fooled, line, x0, SolverOptions{});
  EXPECT_TRUE(mentions(run.contract, "Jacobian has a non-finite entry")) << run.contract.report();
}

}  // namespace
}  // namespace kincal::problems
