#include "kincal/framework/workflows/design_map.hpp"

#include <Eigen/Eigenvalues>
#include <cmath>

namespace kincal {

nlohmann::ordered_json design_configuration_map(const DesignCandidates& candidates,
                                                const std::vector<int>& chosen,
                                                int max_candidates) {
  using Json = nlohmann::ordered_json;
  const MatrixXd& q = candidates.configurations;
  const Eigen::Index n = q.cols();
  Json out;
  if (q.rows() == 0 || n == 0) return out;
  // Each actuator scaled to its range, so that mm and rad weigh alike.
  const Eigen::RowVectorXd mean = q.colwise().mean();
  Eigen::RowVectorXd range = q.colwise().maxCoeff() - q.colwise().minCoeff();
  for (Eigen::Index j = 0; j < n; ++j)
    if (!(range[j] > 0)) range[j] = 1;
  const MatrixXd z = (q.rowwise() - mean).array().rowwise() / range.array();
  const Eigen::SelfAdjointEigenSolver<MatrixXd> eig(z.transpose() * z);
  // Eigenvalues ascending: the last two columns are the principal directions.
  MatrixXd axes = MatrixXd::Zero(n, 2);
  VectorXd variance = VectorXd::Zero(2);
  for (int k = 0; k < 2 && k < n; ++k) {
    axes.col(k) = eig.eigenvectors().col(n - 1 - k);
    variance[k] = std::max(eig.eigenvalues()[n - 1 - k], 0.0);
  }
  const double total = std::max(eig.eigenvalues().sum(), 1e-300);
  const auto point = [&](int row) {
    const Eigen::RowVectorXd p = z.row(row) * axes;
    return Json::array({p[0], p[1]});
  };
  out["axes"] = {
      "principal direction 1 of the candidates' actuator values (each scaled to its "
      "range)",
      "principal direction 2"};
  out["explained"] = {variance[0] / total, variance[1] / total};
  out["candidates_total"] = q.rows();
  Json sample = Json::array();
  const Eigen::Index step =
      std::max<Eigen::Index>(1, (q.rows() + max_candidates - 1) / std::max(max_candidates, 1));
  for (Eigen::Index r = 0; r < q.rows(); r += step) sample.push_back(point(static_cast<int>(r)));
  out["candidates"] = sample;
  Json picked = Json::array();
  for (int c : chosen)
    picked.push_back(point(candidates.configuration[static_cast<std::size_t>(c)]));
  out["chosen"] = picked;
  return out;
}

}  // namespace kincal
