#pragma once
// The implicit-loop formulation of a closed chain's calibration (Wampler, Hollerbach & Arai
// 1995; docs/theory.md): every configuration's pose is an unknown beside the parameters, and
// each configuration contributes its closure constraints, weighted, and its readings:
//   x = [free parameters (p) | local pose coordinates of configuration 1 (Dof) | ... ],
//   residuals of configuration j = [ w g(params, q_j, pose_j) ; reading errors / std ].
// Pose j is reference_pose(j) moved by its Dof local coordinates, the reference being forward
// kinematics at the starting parameters; at x = initial_x() every closure holds to the
// forward kinematics' tolerance and the cost is the nested problem's.
//
// As a LeastSquaresProblem its Jacobian is dense (m (Dof + k) x (p + Dof m)): for tests and
// generic backends on small problems. lm solves it by a Schur complement on the structured
// access below (solvers/schur_levenberg_marquardt.hpp).

#include <memory>
#include <string>
#include <vector>

#include "kincal/framework/calibration/calibration_problem.hpp"
#include "kincal/framework/kinematics/closed_chain_mechanism.hpp"

namespace kincal {

class ImplicitCalibrationProblem : public LeastSquaresProblem {
 public:
  /// The closure weight w that makes the constraints hold to `tolerance` (the forward
  /// kinematics' tolerance, in the constraints' unit) at the solution when the readings'
  /// whitened residuals are about 1 / sqrt(min std): w = 1 / sqrt(tolerance * min std).
  static double default_weight(const MeasurementModel& model);

  /// Whether `model`'s mechanism is a closed chain this formulation handles (Dof 3 or 6).
  static bool applicable(const MeasurementModel& model);

  /// From the nested problem: the same model, data, parameters and free set. Runs forward
  /// kinematics at the nested problem's starting parameters for the reference poses; a
  /// configuration where it fails makes start_failure() non-empty ("configuration 12:
  /// forward kinematics ...", the nested problem's words) and its block fail. `weight` <= 0
  /// takes default_weight(). Throws std::invalid_argument when !applicable(model).
  explicit ImplicitCalibrationProblem(std::shared_ptr<const CalibrationProblem> nested,
                                      double weight = 0);

  int num_parameters() const override;
  int num_residual_blocks() const override { return nested_->num_residual_blocks(); }
  int residuals_per_block() const override { return dof_ + nested_->residuals_per_block(); }
  std::vector<std::string> parameter_names() const override;
  bool evaluate_block(int block, const VectorXd& x, Eigen::Ref<VectorXd> residuals,
                      Eigen::Ref<MatrixXd>* jacobian, std::string* why) const override;
  /// Configuration `block`'s residuals at the free parameters `theta` and its own local pose
  /// coordinates `local` (dof() of them), with, where non-null, their Jacobians by theta
  /// (residuals_per_block() x num_free_parameters()) and by local (residuals_per_block() x
  /// dof()): evaluate_block's rows without the other poses' zero columns, for a backend that
  /// sees the block structure (Ceres' Schur solvers).
  bool evaluate_configuration(int block, const VectorXd& theta,
                              const Eigen::Ref<const VectorXd>& local,
                              Eigen::Ref<VectorXd> residuals, Eigen::Ref<MatrixXd>* J_theta,
                              Eigen::Ref<MatrixXd>* J_local, std::string* why) const;

  const CalibrationProblem& nested() const { return *nested_; }
  std::shared_ptr<const CalibrationProblem> nested_ptr() const { return nested_; }
  int dof() const { return dof_; }
  /// Free parameters of the nested problem (the head of x).
  int num_free_parameters() const { return nested_->num_parameters(); }
  double weight() const { return weight_; }
  /// Forward kinematics at the starting parameters (home pose where it failed or nothing
  /// was measured).
  const Pose& reference_pose(int block) const { return reference_[block]; }
  /// Whether configuration `block` has a measured reading (else it has no residual).
  bool measured(int block) const { return measured_[block] != 0; }
  /// Empty, or why forward kinematics failed at the start (the first configuration).
  const std::string& start_failure() const { return start_failure_; }
  /// [the nested problem's start | zeros].
  VectorXd initial_x() const;

  /// The mechanism as a closed chain of `Dof` constraints; null for another Dof.
  template <int Dof>
  const ClosedChainMechanism<Dof>* chain() const {
    return dynamic_cast<const ClosedChainMechanism<Dof>*>(&nested_->model().mechanism());
  }

 private:
  template <int Dof>
  bool evaluate_configuration_of(int block, const VectorXd& theta,
                                 const Eigen::Ref<const VectorXd>& local,
                                 Eigen::Ref<VectorXd> residuals, Eigen::Ref<MatrixXd>* J_theta,
                                 Eigen::Ref<MatrixXd>* J_local, std::string* why) const;

  std::shared_ptr<const CalibrationProblem> nested_;
  int dof_ = 0;
  double weight_ = 0;
  std::vector<Pose> reference_;
  std::vector<char> measured_;
  std::string start_failure_;
  int failed_block_ = -1;
};

}  // namespace kincal
