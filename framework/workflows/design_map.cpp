#include "kincal/framework/workflows/design_map.hpp"

#include <Eigen/Eigenvalues>
#include <cmath>

namespace kincal {

DesignMap design_configuration_map(const DesignCandidates& candidates,
                                   const std::vector<int>& chosen, int max_candidates) {
  const MatrixXd& q = candidates.configurations;
  const Eigen::Index n = q.cols();
  DesignMap out;
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
    return std::array<double, 2>{p[0], p[1]};
  };
  out.computed = true;
  out.axes = {
      "principal direction 1 of the candidates' actuator values (each scaled to its "
      "range)",
      "principal direction 2"};
  out.explained[0] = variance[0] / total;
  out.explained[1] = variance[1] / total;
  out.candidates_total = q.rows();
  const Eigen::Index step =
      std::max<Eigen::Index>(1, (q.rows() + max_candidates - 1) / std::max(max_candidates, 1));
  for (Eigen::Index r = 0; r < q.rows(); r += step)
    out.candidates.push_back(point(static_cast<int>(r)));
  for (int c : chosen)
    out.chosen.push_back(point(candidates.configuration[static_cast<std::size_t>(c)]));
  return out;
}

nlohmann::ordered_json to_json(const DesignMap& map) {
  using Json = nlohmann::ordered_json;
  Json out;
  if (!map.computed) return out;
  out["axes"] = map.axes;
  out["explained"] = {map.explained[0], map.explained[1]};
  out["candidates_total"] = map.candidates_total;
  const auto points = [](const std::vector<std::array<double, 2>>& list) {
    Json a = Json::array();
    for (const auto& p : list) a.push_back(Json::array({p[0], p[1]}));
    return a;
  };
  out["candidates"] = points(map.candidates);
  out["chosen"] = points(map.chosen);
  return out;
}

}  // namespace kincal
