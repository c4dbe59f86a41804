// Experiment design: criteria, random designs, the rows of a design, and run_design, which
// chains the stages (design_candidates.cpp, design_exchange.cpp, design_bound.cpp).
#include "kincal/framework/design/experiment_design.hpp"

#include <Eigen/Cholesky>
#include <Eigen/Eigenvalues>
#include <Eigen/SVD>
#include <algorithm>
#include <cmath>
#include <limits>
#include <numeric>
#include <stdexcept>

#include "kincal/framework/base/random.hpp"
#include "kincal/framework/design/design_stages.hpp"

namespace kincal {

using namespace design_detail;

const char* to_string(DesignCriterion criterion) {
  switch (criterion) {
    case DesignCriterion::kD:
      return "D";
    case DesignCriterion::kA:
      return "A";
    case DesignCriterion::kE:
      return "E";
    case DesignCriterion::kI:
      return "I";
  }
  return "?";
}

DesignCriterion parse_design_criterion(const std::string& text) {
  if (text == "D" || text == "d") return DesignCriterion::kD;
  if (text == "A" || text == "a") return DesignCriterion::kA;
  if (text == "E" || text == "e") return DesignCriterion::kE;
  if (text == "I" || text == "i") return DesignCriterion::kI;
  throw std::invalid_argument("unknown design criterion '" + text + "' (expected D, A, E or I)");
}

MatrixXd design_information(const DesignCandidates& candidates, const std::vector<int>& chosen,
                            const DesignSetup& setup) {
  MatrixXd M = setup.base_information;
  for (int c : chosen) {
    const auto X = candidates.rows.middleRows(
        candidates.row_offset[c], candidates.row_offset[c + 1] - candidates.row_offset[c]);
    M.noalias() += X.transpose() * X;
  }
  return M;
}

double criterion_value(DesignCriterion criterion, const MatrixXd& M, const DesignSetup& setup) {
  const int n = static_cast<int>(M.rows());
  const Eigen::SelfAdjointEigenSolver<MatrixXd> eig(M);
  const VectorXd& l = eig.eigenvalues();
  const double inf = std::numeric_limits<double>::infinity();
  if (criterion == DesignCriterion::kE) return l[0];
  if (criterion == DesignCriterion::kD) return l[0] > 0 ? l.array().log().sum() : -inf;
  if (!(l[0] > 1e-14 * std::max(l[n - 1], 1e-300))) return inf;
  const MatrixXd inverse =
      eig.eigenvectors() * l.cwiseInverse().asDiagonal() * eig.eigenvectors().transpose();
  if (criterion == DesignCriterion::kA) return inverse.trace() / n;
  return (setup.workspace_weight * inverse).trace();
}

MatrixXd design_covariance(const MatrixXd& M, const DesignSetup& setup) {
  const int n = static_cast<int>(M.rows());
  const Eigen::SelfAdjointEigenSolver<MatrixXd> eig(M);
  const VectorXd& l = eig.eigenvalues();
  if (!(l[0] > 1e-14 * std::max(l[n - 1], 1e-300)))
    return MatrixXd::Constant(n, n, std::numeric_limits<double>::quiet_NaN());
  const MatrixXd inverse =
      eig.eigenvectors() * l.cwiseInverse().asDiagonal() * eig.eigenvectors().transpose();
  return setup.scale.asDiagonal() * inverse * setup.scale.asDiagonal();
}

std::vector<int> random_design(const DesignCandidates& candidates, int count, std::uint64_t seed) {
  // Candidates of the random configurations only, in order.
  std::vector<int> pool;
  for (int c = 0; c < candidates.size(); ++c)
    if (candidates.configuration[c] >= candidates.num_corners) pool.push_back(c);
  if (static_cast<int>(pool.size()) < count)
    throw std::invalid_argument("only " + std::to_string(pool.size()) +
                                " random candidates for a random design of " +
                                std::to_string(count));
  Random rng(derive_seed(seed, kRandomStream));
  for (int i = 0; i < count; ++i) {  // partial Fisher-Yates
    const int j = i + static_cast<int>(rng.uniform01() * (pool.size() - i));
    std::swap(pool[i], pool[j]);
  }
  pool.resize(count);
  return pool;
}

Measurements design_rows(const MeasurementModel& model, const DesignCandidates& candidates,
                         const std::vector<int>& chosen) {
  std::vector<int> order;  // configurations in order of first choice
  std::vector<int> row_of(candidates.configurations.rows(), -1);
  for (int c : chosen) {
    const int q = candidates.configuration[c];
    if (row_of[q] < 0) {
      row_of[q] = static_cast<int>(order.size());
      order.push_back(q);
    }
  }
  Measurements m;
  m.actuators.resize(order.size(), candidates.configurations.cols());
  m.readings = MatrixXd::Constant(order.size(), model.num_readings(),
                                  std::numeric_limits<double>::quiet_NaN());
  for (std::size_t r = 0; r < order.size(); ++r)
    m.actuators.row(r) = candidates.configurations.row(order[r]);
  for (int c : chosen) {
    const int s = candidates.sensor[c];
    m.readings.row(row_of[candidates.configuration[c]])
        .segment(model.sensor_reading_offset(s), model.sensors()[s]->num_readings())
        .setZero();
  }
  if (model.sensors_can_miss()) {
    // The readings a sensor would not take there (a camera's points out of view) stay
    // missing, as the candidate left them out (make_design_candidates).
    const VectorXd nominal = model.parameters().nominal_values();
    auto ws = model.make_workspace();
    VectorXd seen(model.num_readings());
    for (int r = 0; r < m.size(); ++r) {
      const VectorXd q = m.actuators.row(r).transpose();
      const ForwardKinematicsResult fk = model.predict(nominal, q, seen, nullptr, ws);
      if (!fk.ok()) continue;  // a candidate is reachable: not reached here
      model.simulate_at_pose(nominal, fk.pose, seen);
      for (int k = 0; k < model.num_readings(); ++k)
        if (std::isnan(seen[k])) m.readings(r, k) = std::numeric_limits<double>::quiet_NaN();
    }
  }
  return m;
}

DesignRun run_design(const MeasurementModel& model, const DesignOptions& options,
                     const Measurements* existing) {
  DesignRun run;
  run.setup = make_design_setup(model, options, existing);
  run.candidates = make_design_candidates(model, run.setup, options);
  run.result = choose_design(run.candidates, run.setup, options);
  run.rows = design_rows(model, run.candidates, run.result.chosen);
  return run;
}

}  // namespace kincal
