#include "benchmarks/cramer_rao.hpp"

#include <Eigen/SVD>
#include <cmath>

#include "kincal/framework/least_squares/uncertainty.hpp"

namespace kincal::bench {

CramerRaoPrediction predict_cramer_rao(const Scenario& scenario) {
  CramerRaoPrediction p;
  const auto problem = scenario.make_problem();
  const VectorXd x_true = problem->free_parameters(scenario.truth);
  VectorXd r;
  MatrixXd J;
  if (!problem->evaluate(x_true, &r, &J)) return p;
  const int n = static_cast<int>(x_true.size());
  p.sigma = scenario.options.noise_for(kincal::kMillimetre) / std::sqrt(3.0);
  const Eigen::JacobiSVD<MatrixXd> svd(J);
  const VectorXd& s = svd.singularValues();
  p.condition_number = s[s.size() - 1] > 0 ? s[0] / s[s.size() - 1] : INFINITY;
  const MatrixXd cov = parameter_covariance(J, p.sigma);
  p.parameter_mean_square = cov.trace() / n;

  // Pose covariance at each validation pose: J_f Cov J_f^T, J_f = free columns of
  // J_pose_params (sensor parameters do not move the pose: zero columns).
  const Mechanism& mechanism = scenario.model->mechanism();
  const int n_mech = mechanism.num_parameters();
  const auto truth = scenario.truth.head(n_mech);
  Matrix6Xd J_pose_params(6, n_mech);
  Matrix6Xd J_free = Matrix6Xd::Zero(6, n);
  const int count = static_cast<int>(scenario.validation_poses.size());
  for (int j = 0; j < count; ++j) {
    mechanism.pose_jacobian_params(truth, scenario.validation_actuators.row(j).transpose(),
                                   scenario.validation_poses[j], J_pose_params);
    for (int i = 0; i < n; ++i)
      if (scenario.free_indices[i] < n_mech)
        J_free.col(i) = J_pose_params.col(scenario.free_indices[i]);
    const Matrix6d pose_cov = J_free * cov * J_free.transpose();
    p.position_mean_square += pose_cov.topLeftCorner<3, 3>().trace();
    p.orientation_mean_square += pose_cov.bottomRightCorner<3, 3>().trace();
  }
  if (count > 0) {
    p.position_mean_square /= count;
    p.orientation_mean_square /= count;
  }
  p.ok = true;
  return p;
}

}  // namespace kincal::bench
