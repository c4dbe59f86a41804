#include "kincal/framework/analysis/fixed_parameter_sensitivity.hpp"

#include <Eigen/SVD>
#include <algorithm>
#include <cmath>
#include <stdexcept>

#include "kincal/framework/kinematics/units.hpp"

namespace kincal {

SensitivityResult fixed_parameter_sensitivity(std::shared_ptr<const MeasurementModel> model,
                                              const VectorXd& values,
                                              const Measurements& calibration,
                                              const Measurements& workspace,
                                              const std::vector<int>& free, double delta_mm,
                                              double delta_rad) {
  const int n = model->num_parameters();
  std::vector<bool> is_free(n, false);
  for (int i : free) is_free[i] = true;
  std::vector<int> fixed;
  for (int i = 0; i < n; ++i)
    if (!is_free[i]) fixed.push_back(i);

  // Whitened residual Jacobian over free then fixed parameters, at the model's values.
  std::vector<int> columns = free;
  columns.insert(columns.end(), fixed.begin(), fixed.end());
  const CalibrationProblem problem(model, calibration, values, columns);
  VectorXd r;
  MatrixXd J;
  std::string why;
  if (!problem.evaluate(problem.initial_free_parameters(), &r, &J, &why))
    throw std::runtime_error("cannot evaluate the identification Jacobian: " + why);
  const int nf = static_cast<int>(free.size());
  const MatrixXd Jf = J.leftCols(nf);

  // pinv(J_f) through the SVD of the column-scaled J_f (the scaling keeps mm and rad
  // columns comparable); directions below 1e-10 of the largest are treated as null.
  SensitivityResult result;
  result.num_free = nf;
  VectorXd scale = VectorXd::Ones(nf);
  for (int c = 0; c < nf; ++c)
    if (Jf.col(c).norm() > 0) scale[c] = 1.0 / Jf.col(c).norm();
  Eigen::JacobiSVD<MatrixXd> svd;
  if (nf > 0) {
    svd.compute(Jf * scale.asDiagonal(), Eigen::ComputeThinU | Eigen::ComputeThinV);
    svd.setThreshold(1e-10);
    result.free_rank = static_cast<int>(svd.rank());
  }

  // Residual rows back in the readings' units.
  const int k = model->num_readings();
  VectorXd row_std(J.rows());
  for (int i = 0; i < J.rows(); ++i) row_std[i] = model->reading_std()[i % k];
  int measured = 0;
  for (int c = 0; c < calibration.size(); ++c)
    for (int i = 0; i < k; ++i) measured += std::isnan(calibration.readings(c, i)) ? 0 : 1;

  // Pose Jacobians at the workspace configurations (mechanism parameters only).
  const Mechanism& mechanism = model->mechanism();
  const int nm = static_cast<int>(mechanism.parameters().size());
  const auto mechanism_values = values.head(nm);
  std::vector<Matrix6Xd> P;
  for (int c = 0; c < workspace.size(); ++c) {
    const VectorXd q = workspace.actuators.row(c).transpose();
    const ForwardKinematicsResult fk = mechanism.forward_kinematics(
        mechanism_values, q, mechanism.home_pose(), model->forward_kinematics_options());
    if (!fk.ok())
      throw std::runtime_error("forward kinematics fails at workspace configuration " +
                               std::to_string(c + 1) + ": " + fk.describe());
    Matrix6Xd Jp(6, nm);
    mechanism.pose_jacobian_params(mechanism_values, q, fk.pose, Jp);
    P.push_back(Jp);
  }

  for (std::size_t f = 0; f < fixed.size(); ++f) {
    const Parameter& p = model->parameters()[fixed[f]];
    FixedParameterSensitivity row;
    row.name = p.name;
    row.unit = p.unit;
    row.delta = p.unit == kRadian ? delta_rad : delta_mm;
    const VectorXd jk = J.col(nf + static_cast<int>(f)) * row.delta;
    VectorXd dx = VectorXd::Zero(nf);
    if (nf > 0) dx = scale.asDiagonal() * svd.solve(jk);
    const VectorXd left = (jk - Jf * dx).cwiseProduct(row_std);
    row.residual_rms = measured ? std::sqrt(left.squaredNorm() / measured) : 0.0;
    for (const Matrix6Xd& Jp : P) {
      Vector6d e = Vector6d::Zero();
      if (fixed[f] < nm) e += Jp.col(fixed[f]) * row.delta;
      for (int c = 0; c < nf; ++c)
        if (free[c] < nm) e -= Jp.col(free[c]) * dx[c];
      const double position = e.head<3>().norm(), angle = e.tail<3>().norm();
      row.position_mean += position;
      row.orientation_mean += angle;
      row.position_max = std::max(row.position_max, position);
      row.orientation_max = std::max(row.orientation_max, angle);
    }
    if (!P.empty()) {
      row.position_mean /= static_cast<double>(P.size());
      row.orientation_mean /= static_cast<double>(P.size());
    }
    result.rows.push_back(row);
  }
  return result;
}

nlohmann::ordered_json to_json(const SensitivityResult& s) {
  nlohmann::ordered_json rows = nlohmann::ordered_json::array();
  for (const auto& r : s.rows)
    rows.push_back({{"name", r.name},
                    {"unit", r.unit},
                    {"error", r.delta},
                    {"residual_rms", r.residual_rms},
                    {"position_mean_mm", r.position_mean},
                    {"position_max_mm", r.position_max},
                    {"orientation_mean_rad", r.orientation_mean},
                    {"orientation_max_rad", r.orientation_max}});
  return rows;
}

}  // namespace kincal
