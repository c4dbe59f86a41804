#pragma once
// Problems shared by the solver tests: the paper's scenarios and a small generic curve fit.

#include <gtest/gtest.h>
#include <cmath>
#include <cstdint>

#include <cctype>
#include <map>
#include <memory>
#include <string>
#include <utility>
#include <vector>

#include "kincal/framework/calibration/simulation.hpp"
#include "kincal/framework/least_squares/solver_registry.hpp"
#include "kincal/models/presets.hpp"

namespace kincal::testing {

/// `options` with `solver`'s settings parsed from key=value text, as the faces do.
inline SolverOptions with_settings(const Solver& solver,
                                   const std::map<std::string, std::string>& text,
                                   SolverOptions options = {}) {
  options.backend = solver.parse_settings(text);
  return options;
}

/// Whether `solver` refuses the settings `text`: when parsing them, or when checking them
/// together with the other options (Ceres' own rules).
inline bool refuses(const Solver& solver, const std::map<std::string, std::string>& text) {
  try {
    solver.check_options(with_settings(solver, text));
    return false;
  } catch (const InvalidSolverOptions&) {
    return true;
  }
}

/// The paper's Table 2 case `case_id` on `model` (the cube hexapod, or a variant of it with
/// other free parameters), drawn from `seed`.
inline Scenario paper_scenario(std::shared_ptr<MeasurementModel> model, int case_id,
                               std::uint64_t seed, double param_error = 5, int validation = 20) {
  ScenarioOptions options;
  options.num_configurations = paper_case(case_id).num_configurations;
  options.noise_half_width.set(kincal::kMillimetre, paper_case(case_id).noise_half_width);
  options.param_error_half_width.set(kincal::kMillimetre, param_error);
  options.num_validation = validation;
  options.seed = seed;
  return make_scenario(std::move(model), options);
}

/// The paper's Table 2 case `case_id` on the cube hexapod, drawn from `seed`.
inline Scenario paper_scenario(int case_id, std::uint64_t seed, double param_error = 5,
                               int validation = 20) {
  return paper_scenario(make_cube_hexapod(), case_id, seed, param_error, validation);
}

/// y = a exp(-b t) + c at 20 points, noise-free: 3 parameters, minimum (2, 0.7, 0.3), cost 0.
/// Small enough for derivative-free algorithms to be tested for real.
class ExponentialFit : public LeastSquaresProblem {
 public:
  int num_parameters() const override { return 3; }
  int num_residual_blocks() const override { return 20; }
  int residuals_per_block() const override { return 1; }
  bool evaluate_block(int block, const VectorXd& x, Eigen::Ref<VectorXd> residuals,
                      Eigen::Ref<MatrixXd>* jacobian, std::string*) const override {
    const double t = 0.25 * block, e = std::exp(-x[1] * t);
    residuals[0] = x[0] * e + x[2] - (2 * std::exp(-0.7 * t) + 0.3);
    if (jacobian) *jacobian << e, -x[0] * t * e, 1;
    return true;
  }
  static VectorXd start() { return Eigen::Vector3d(1, 0.3, 0); }
  static VectorXd solution() { return Eigen::Vector3d(2, 0.7, 0.3); }
};

/// The same fit whose residuals exist only for a <= 1.5, like forward kinematics that works in
/// part of the parameter space: the minimum (a = 2) is beyond the fence, so every backend
/// meets uncomputable trial points in the middle of the solve.
class FencedFit : public ExponentialFit {
 public:
  static constexpr double kFence = 1.5;
  static constexpr const char* kReason = "beyond the fence (test problem)";
  bool evaluate_block(int block, const VectorXd& x, Eigen::Ref<VectorXd> residuals,
                      Eigen::Ref<MatrixXd>* jacobian, std::string* why) const override {
    if (x[0] > kFence) {
      if (why) *why = kReason;
      return false;
    }
    return ExponentialFit::evaluate_block(block, x, residuals, jacobian, why);
  }
};

/// Empty when `name` can be created in this build; otherwise why not, in the registry's words
/// (for a backend left out of the build they name its KINCAL_WITH_<NAME> option). Tests of a
/// backend skip with this reason.
/// Every backend name, those left out of the build included (their tests then skip with the
/// reason): the parameters of the suites every backend runs.
inline std::vector<std::string> every_backend() {
  std::vector<std::string> names = SolverRegistry::global().featured_names();
  for (const auto& missing : SolverRegistry::global().unavailable()) names.push_back(missing.name);
  return names;
}

/// A backend name as a GoogleTest parameter name ("nlopt:LD_LBFGS" -> "nlopt_LD_LBFGS").
inline std::string backend_test_name(const ::testing::TestParamInfo<std::string>& info) {
  std::string name = info.param;
  for (char& c : name)
    if (!std::isalnum(static_cast<unsigned char>(c))) c = '_';
  return name;
}

inline std::string why_not_built(const std::string& name) {
  try {
    SolverRegistry::global().create(name);
    return "";
  } catch (const InvalidSolverOptions& e) {
    return e.what();
  }
}

/// A stop where the backend's own test fired at a point that is not stationary by kincal's
/// tests (docs/solvers.md, "The honesty contract"): reported `failed`, "stalled: ...".
inline bool stalled(const Summary& summary) {
  return summary.termination == TerminationType::kFailed &&
         summary.message.rfind("stalled", 0) == 0;
}

/// The exponential fit with a non-finite value in every evaluation: a Jacobian entry (NaN or
/// infinite, as a model whose derivative divides by zero) or a residual (NaN). Evaluation
/// "succeeds": only the values say that nothing can be done with them.
class NonFiniteFit : public ExponentialFit {
 public:
  enum class Where { kJacobianNan, kJacobianInfinite, kResidualNan };
  /// Everywhere, or only where a > `fence` (the minimum, a = 2, lies beyond a fence of 1.5).
  explicit NonFiniteFit(Where where, double fence = -HUGE_VAL) : where_(where), fence_(fence) {}
  bool evaluate_block(int block, const VectorXd& x, Eigen::Ref<VectorXd> residuals,
                      Eigen::Ref<MatrixXd>* jacobian, std::string* why) const override {
    ExponentialFit::evaluate_block(block, x, residuals, jacobian, why);
    if (block != 3 || !(x[0] > fence_)) return true;
    if (where_ == Where::kResidualNan) residuals[0] = std::nan("");
    if (jacobian && where_ == Where::kJacobianNan) (*jacobian)(0, 1) = std::nan("");
    if (jacobian && where_ == Where::kJacobianInfinite) (*jacobian)(0, 1) = HUGE_VAL;
    return true;
  }

 private:
  Where where_;
  double fence_;
};

/// Residuals that cannot be computed anywhere, as when forward kinematics fails.
class NowhereComputable : public ExponentialFit {
 public:
  bool evaluate_block(int, const VectorXd&, Eigen::Ref<VectorXd>, Eigen::Ref<MatrixXd>*,
                      std::string* why) const override {
    if (why) *why = "forward kinematics failed";
    return false;
  }
};

}  // namespace kincal::testing
