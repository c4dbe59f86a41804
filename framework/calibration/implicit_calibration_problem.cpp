#include "kincal/framework/calibration/implicit_calibration_problem.hpp"

#include <cmath>
#include <stdexcept>

#include "kincal/framework/calibration/implicit_configuration.hpp"

namespace kincal {

namespace {

int chain_dof(const Mechanism& mechanism) {
  if (dynamic_cast<const ClosedChainMechanism<6>*>(&mechanism)) return 6;
  if (dynamic_cast<const ClosedChainMechanism<3>*>(&mechanism)) return 3;
  return 0;
}

// d(local coordinates at the moved pose) / d(chart coordinates): the chart adds to the
// rotation vector of the reference, and a left perturbation of exp(w) is J_l(w) of it.
template <int Dof>
Eigen::Matrix<double, Dof, Dof> chart_jacobian(const ClosedChainMechanism<Dof>& mechanism,
                                               const Eigen::Matrix<double, Dof, 1>& local) {
  Matrix6d T6 = Matrix6d::Identity();
  if constexpr (Dof == 6) {
    T6.bottomRightCorner<3, 3>() = left_jacobian_so3(local.template tail<3>());
    return T6;
  } else {
    const auto& E = mechanism.motion_basis();
    const Vector6d delta = E * local;
    T6.bottomRightCorner<3, 3>() = left_jacobian_so3(delta.tail<3>());
    const Eigen::Matrix<double, Dof, Dof> EtE = E.transpose() * E;
    return EtE.inverse() * (E.transpose() * T6 * E);
  }
}

}  // namespace

bool ImplicitCalibrationProblem::applicable(const MeasurementModel& model) {
  return chain_dof(model.mechanism()) != 0;
}

double ImplicitCalibrationProblem::default_weight(const MeasurementModel& model) {
  const double tolerance = model.forward_kinematics_options().tolerance;
  const double min_std = model.reading_std().size() ? model.reading_std().minCoeff() : 1.0;
  return 1.0 / std::sqrt(tolerance * min_std);
}

ImplicitCalibrationProblem::ImplicitCalibrationProblem(
    std::shared_ptr<const CalibrationProblem> nested, double weight)
    : nested_(std::move(nested)) {
  const MeasurementModel& model = nested_->model();
  dof_ = chain_dof(model.mechanism());
  if (dof_ == 0)
    throw std::invalid_argument(
        "the implicit formulation needs a closed-chain mechanism with 3 "
        "or 6 constraints; " +
        model.mechanism().type() + " is not one");
  weight_ = weight > 0 ? weight : default_weight(model);
  const Mechanism& mechanism = model.mechanism();
  const VectorXd start = nested_->full_parameters(nested_->initial_free_parameters());
  const Measurements& data = nested_->data();
  reference_.assign(static_cast<std::size_t>(data.size()), mechanism.home_pose());
  measured_.assign(static_cast<std::size_t>(data.size()), 0);
  for (int j = 0; j < data.size(); ++j) {
    if (data.readings.row(j).array().isNaN().all()) continue;  // no residual: no pose needed
    measured_[j] = 1;
    const ForwardKinematicsResult fk = mechanism.forward_kinematics(
        start.head(mechanism.num_parameters()), data.actuators.row(j).transpose(),
        mechanism.home_pose(), model.forward_kinematics_options());
    if (fk.ok()) {
      reference_[j] = fk.pose;
    } else if (failed_block_ < 0) {
      failed_block_ = j;
      start_failure_ =
          "configuration " + std::to_string(j + 1) + ": forward kinematics " + fk.describe();
    }
  }
}

int ImplicitCalibrationProblem::num_parameters() const {
  return nested_->num_parameters() + dof_ * nested_->num_residual_blocks();
}

std::vector<std::string> ImplicitCalibrationProblem::parameter_names() const {
  std::vector<std::string> names = nested_->parameter_names();
  for (int j = 0; j < num_residual_blocks(); ++j)
    for (int c = 0; c < dof_; ++c)
      names.push_back("pose" + std::to_string(j + 1) + "." + std::to_string(c));
  return names;
}

VectorXd ImplicitCalibrationProblem::initial_x() const {
  VectorXd x = VectorXd::Zero(num_parameters());
  x.head(nested_->num_parameters()) = nested_->initial_free_parameters();
  return x;
}

bool ImplicitCalibrationProblem::evaluate_block(int block, const VectorXd& x,
                                                Eigen::Ref<VectorXd> residuals,
                                                Eigen::Ref<MatrixXd>* jacobian,
                                                std::string* why) const {
  const int p = nested_->num_parameters();
  thread_local VectorXd theta;
  theta = x.head(p);
  const auto local = x.segment(p + dof_ * block, dof_);
  if (!jacobian)
    return evaluate_configuration(block, theta, local, residuals, nullptr, nullptr, why);
  // The block's row: its own pose's columns and the parameters'; every other pose's are zero.
  jacobian->setZero();
  Eigen::Ref<MatrixXd> J_theta = jacobian->leftCols(p);
  Eigen::Ref<MatrixXd> J_local = jacobian->middleCols(p + dof_ * block, dof_);
  return evaluate_configuration(block, theta, local, residuals, &J_theta, &J_local, why);
}

bool ImplicitCalibrationProblem::evaluate_configuration(int block, const VectorXd& theta,
                                                        const Eigen::Ref<const VectorXd>& local,
                                                        Eigen::Ref<VectorXd> residuals,
                                                        Eigen::Ref<MatrixXd>* J_theta,
                                                        Eigen::Ref<MatrixXd>* J_local,
                                                        std::string* why) const {
  return dof_ == 6
             ? evaluate_configuration_of<6>(block, theta, local, residuals, J_theta, J_local, why)
             : evaluate_configuration_of<3>(block, theta, local, residuals, J_theta, J_local, why);
}

template <int Dof>
bool ImplicitCalibrationProblem::evaluate_configuration_of(int block, const VectorXd& theta,
                                                           const Eigen::Ref<const VectorXd>& local,
                                                           Eigen::Ref<VectorXd> residuals,
                                                           Eigen::Ref<MatrixXd>* J_theta,
                                                           Eigen::Ref<MatrixXd>* J_local,
                                                           std::string* why) const {
  if (block == failed_block_) {
    if (why) *why = start_failure_;
    return false;
  }
  const bool jacobians = J_theta || J_local;
  if (J_theta) J_theta->setZero();
  if (J_local) J_local->setZero();
  if (!measured_[block]) {
    residuals.setZero();
    return true;
  }
  const ClosedChainMechanism<Dof>& mechanism = *chain<Dof>();
  const MeasurementModel& model = nested_->model();
  const Measurements& data = nested_->data();
  const Eigen::Matrix<double, Dof, 1> chart = local;
  const Pose pose = moved_pose(mechanism, reference_[block], chart);
  thread_local ImplicitConfiguration<Dof> c;
  thread_local VectorXd full, measured_row;
  full = nested_->full_parameters(theta);
  measured_row = data.readings.row(block).transpose();
  std::string reason;
  if (!evaluate_implicit_configuration(model, mechanism, full,
                                       data.actuators.row(block).transpose(), measured_row, pose,
                                       jacobians, c, why ? &reason : nullptr)) {
    if (why) *why = "configuration " + std::to_string(block + 1) + ": " + reason;
    return false;
  }
  residuals.head<Dof>() = weight_ * c.g;
  residuals.tail(c.errors.size()) = c.errors;
  if (J_theta) {
    // The constraints through the mechanism's parameters, the readings through the sensors'.
    thread_local typename ClosedChainMechanism<Dof>::ParamsJacobian G_params;
    G_params.resize(Dof, mechanism.num_parameters());
    mechanism.constraint_jacobian_params(full.head(mechanism.num_parameters()),
                                         data.actuators.row(block).transpose(), pose, G_params);
    const auto& free = nested_->free_indices();
    for (Eigen::Index i = 0; i < theta.size(); ++i) {
      const int f = free[static_cast<std::size_t>(i)];
      if (f < mechanism.num_parameters()) J_theta->col(i).head<Dof>() = weight_ * G_params.col(f);
      J_theta->col(i).tail(c.errors.size()) = c.H_params.col(f);
    }
  }
  if (J_local) {
    // The configuration's own pose, through the chart.
    const Eigen::Matrix<double, Dof, Dof> T = chart_jacobian(mechanism, chart);
    J_local->topRows(Dof) = weight_ * c.G_pose * T;
    J_local->bottomRows(c.errors.size()) = c.H_pose * T;
  }
  return true;
}

template bool ImplicitCalibrationProblem::evaluate_configuration_of<3>(
    int, const VectorXd&, const Eigen::Ref<const VectorXd>&, Eigen::Ref<VectorXd>,
    Eigen::Ref<MatrixXd>*, Eigen::Ref<MatrixXd>*, std::string*) const;
template bool ImplicitCalibrationProblem::evaluate_configuration_of<6>(
    int, const VectorXd&, const Eigen::Ref<const VectorXd>&, Eigen::Ref<VectorXd>,
    Eigen::Ref<MatrixXd>*, Eigen::Ref<MatrixXd>*, std::string*) const;

}  // namespace kincal
