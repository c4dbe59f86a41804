// kincal-implicit-ceres: Ceres on the implicit-loop formulation, the way issue 24 asked for it
// (its Schur solvers on the pose blocks), against kincal's own Schur-complement lm, on the
// paper's case 5 (seed 1, from nominal). Ceres sees each configuration as one residual block
// over two parameter blocks, the free parameters and that configuration's pose coordinates
// (ImplicitCalibrationProblem::evaluate_configuration), and eliminates the pose blocks first:
// DENSE_SCHUR (Levenberg-Marquardt or dogleg steps), or DENSE_QR on the same blocks to tell the
// linear algebra from the steps. For
// each closure weight w: iterations, the nested cost at the parameters returned, and their
// distance from the nested lm's estimate. Figures and why the backend falls back to the nested
// formulation: docs/benchmarks.md ("Implicit formulation").
//
//   kincal-implicit-ceres [MAX_ITERATIONS=2000]

#include <ceres/ceres.h>

#include <chrono>
#include <cstdio>
#include <cstdlib>
#include <memory>
#include <string>

#include "kincal/framework/calibration/implicit_calibration_problem.hpp"
#include "kincal/framework/calibration/simulation.hpp"
#include "kincal/framework/least_squares/solver_registry.hpp"
#include "kincal/models/presets.hpp"

namespace kincal {
namespace {

// One configuration's residuals over [free parameters | its pose coordinates].
class ConfigurationCost final : public ceres::CostFunction {
 public:
  ConfigurationCost(const ImplicitCalibrationProblem& problem, int block)
      : problem_(problem), block_(block) {
    set_num_residuals(problem.residuals_per_block());
    mutable_parameter_block_sizes()->push_back(problem.num_free_parameters());
    mutable_parameter_block_sizes()->push_back(problem.dof());
  }

  bool Evaluate(double const* const* parameters, double* residuals,
                double** jacobians) const override {
    const int p = problem_.num_free_parameters(), dof = problem_.dof();
    const int k = problem_.residuals_per_block();
    const VectorXd theta = Eigen::Map<const VectorXd>(parameters[0], p);
    const Eigen::Map<const VectorXd> local(parameters[1], dof);
    Eigen::Map<VectorXd> r(residuals, k);
    MatrixXd J_theta(k, p), J_local(k, dof);
    Eigen::Ref<MatrixXd> theta_ref(J_theta), local_ref(J_local);
    const bool want_theta = jacobians && jacobians[0], want_local = jacobians && jacobians[1];
    if (!problem_.evaluate_configuration(block_, theta, local, r, want_theta ? &theta_ref : nullptr,
                                         want_local ? &local_ref : nullptr, nullptr) ||
        !r.allFinite())
      return false;
    using RowMajor = Eigen::Matrix<double, Eigen::Dynamic, Eigen::Dynamic, Eigen::RowMajor>;
    if (want_theta) Eigen::Map<RowMajor>(jacobians[0], k, p) = J_theta;
    if (want_local) Eigen::Map<RowMajor>(jacobians[1], k, dof) = J_local;
    return true;
  }

 private:
  const ImplicitCalibrationProblem& problem_;
  int block_;
};

struct Run {
  int iterations = 0;
  double cost = 0, off_mm = 0, ms = 0;
  std::string message;
};

Run solve_with_ceres(const ImplicitCalibrationProblem& problem, const VectorXd& reference,
                     ceres::LinearSolverType linear_solver, ceres::TrustRegionStrategyType region,
                     int max_iterations) {
  const auto start = std::chrono::steady_clock::now();
  VectorXd x = problem.nested().initial_free_parameters();
  const int m = problem.num_residual_blocks(), dof = problem.dof();
  VectorXd poses = VectorXd::Zero(static_cast<Eigen::Index>(m) * dof);
  ceres::Problem ceres_problem;
  auto ordering = std::make_shared<ceres::ParameterBlockOrdering>();
  for (int j = 0; j < m; ++j) {
    double* pose = poses.data() + static_cast<Eigen::Index>(j) * dof;
    ceres_problem.AddResidualBlock(new ConfigurationCost(problem, j), nullptr, x.data(), pose);
    ordering->AddElementToGroup(pose, 0);  // eliminated first
  }
  ordering->AddElementToGroup(x.data(), 1);
  ceres::Solver::Options options;
  options.linear_solver_type = linear_solver;
  options.trust_region_strategy_type = region;
  options.linear_solver_ordering = ordering;
  options.max_num_iterations = max_iterations;
  options.logging_type = ceres::SILENT;
  ceres::Solver::Summary summary;
  ceres::Solve(options, &ceres_problem, &summary);
  Run run;
  run.ms =
      std::chrono::duration<double, std::milli>(std::chrono::steady_clock::now() - start).count();
  run.iterations = static_cast<int>(summary.iterations.size()) - 1;
  run.cost = problem.nested().cost(x);
  run.off_mm = (x - reference).lpNorm<Eigen::Infinity>();
  run.message = ceres::TerminationTypeToString(summary.termination_type);
  return run;
}

Run solve_with_lm(const ImplicitCalibrationProblem& problem, const VectorXd& reference,
                  int max_iterations) {
  const auto start = std::chrono::steady_clock::now();
  VectorXd x = problem.nested().initial_free_parameters();
  SolverOptions options;
  options.max_iterations = max_iterations;
  const Summary summary =
      SolverRegistry::global().create("lm")->solve_implicit(problem, x, options);
  Run run;
  run.ms =
      std::chrono::duration<double, std::milli>(std::chrono::steady_clock::now() - start).count();
  run.iterations = summary.iterations;
  run.cost = summary.final_cost;
  run.off_mm = (x - reference).lpNorm<Eigen::Infinity>();
  run.message = to_string(summary.termination);
  return run;
}

}  // namespace
}  // namespace kincal

int main(int argc, char** argv) {
  using namespace kincal;
  const int max_iterations = argc > 1 ? std::atoi(argv[1]) : 2000;
  ScenarioOptions o;
  o.num_configurations = paper_case(5).num_configurations;
  o.noise_half_width.set(kincal::kMillimetre, paper_case(5).noise_half_width);
  o.num_validation = 0;
  o.seed = 1;
  const Scenario scenario = make_scenario(make_cube_hexapod(), o);
  const auto nested = scenario.make_problem();
  VectorXd reference = nested->initial_free_parameters();
  const Summary nested_lm = SolverRegistry::global().create("lm")->solve(*nested, reference, {});
  std::printf("nested lm: %d iterations, cost %.9e, %s\n", nested_lm.iterations,
              nested_lm.final_cost, to_string(nested_lm.termination));
  std::printf("w solver iterations nested_cost off_mm ms termination\n");
  for (const double w : {1e1, 1e3, 0.0}) {  // 0: the default weight
    const ImplicitCalibrationProblem problem(nested, w);
    const auto print = [&](const char* solver, const Run& run) {
      std::printf("%.3g %s %d %.9e %.3g %.1f %s\n", problem.weight(), solver, run.iterations,
                  run.cost, run.off_mm, run.ms, run.message.c_str());
    };
    print("lm", solve_with_lm(problem, reference, max_iterations));
    print("ceres:dense_schur", solve_with_ceres(problem, reference, ceres::DENSE_SCHUR,
                                                ceres::LEVENBERG_MARQUARDT, max_iterations));
    print("ceres:dense_schur:dogleg",
          solve_with_ceres(problem, reference, ceres::DENSE_SCHUR, ceres::DOGLEG, max_iterations));
    print("ceres:dense_qr", solve_with_ceres(problem, reference, ceres::DENSE_QR,
                                             ceres::LEVENBERG_MARQUARDT, max_iterations));
  }
  return 0;
}
