// Example: a least-squares problem of your own, solved by every backend this kincal has.
// A circle through 12 points: parameters (centre x, centre y, radius), one residual per
// point, |p - c| - r, with its analytic Jacobian. The start is the usual guess (the points'
// centroid, their mean distance from it). Noise-free points, so every least-squares backend
// must find the circle they were drawn from; general minimisers (NLopt) are held to less: a
// lower cost than at the start, and a claim of convergence only at the circle.
//
//   fit_circle            (exit 0 when every backend did what it claims)

#include <cmath>
#include <cstdio>
#include <kincal/framework/least_squares/least_squares_problem.hpp>
#include <kincal/framework/least_squares/solver_registry.hpp>
#include <kincal/version.hpp>
#include <vector>

namespace {

using kincal::MatrixXd;
using kincal::VectorXd;

class CircleFit final : public kincal::LeastSquaresProblem {
 public:
  explicit CircleFit(std::vector<Eigen::Vector2d> points) : points_(std::move(points)) {}

  int num_parameters() const override { return 3; }
  int num_residual_blocks() const override { return static_cast<int>(points_.size()); }
  int residuals_per_block() const override { return 1; }
  std::vector<std::string> parameter_names() const override { return {"cx", "cy", "r"}; }

  // Called concurrently by threaded backends: reads only, writes only its outputs.
  bool evaluate_block(int block, const VectorXd& x, Eigen::Ref<VectorXd> residuals,
                      Eigen::Ref<MatrixXd>* jacobian, std::string* why) const override {
    const Eigen::Vector2d d = points_[block] - x.head<2>();
    const double distance = d.norm();
    if (distance == 0) {  // the centre on a point: no direction, no derivative
      if (why) *why = "centre on point " + std::to_string(block);
      return false;
    }
    residuals[0] = distance - x[2];
    if (jacobian) *jacobian << -d.x() / distance, -d.y() / distance, -1;
    return true;
  }

 private:
  std::vector<Eigen::Vector2d> points_;
};

}  // namespace

int main() {
  using namespace kincal;
  const Eigen::Vector3d circle(3, -1, 2);  // centre (3, -1), radius 2
  std::vector<Eigen::Vector2d> points;
  for (int i = 0; i < 12; ++i) {
    const double angle = 0.5 * i;  // 0 .. 5.5 rad: most of the circle, unevenly
    points.emplace_back(circle.x() + circle.z() * std::cos(angle),
                        circle.y() + circle.z() * std::sin(angle));
  }
  const CircleFit problem(points);

  Eigen::Vector2d centroid = Eigen::Vector2d::Zero();
  for (const auto& p : points) centroid += p / points.size();
  double radius = 0;
  for (const auto& p : points) radius += (p - centroid).norm() / points.size();
  const Eigen::Vector3d start(centroid.x(), centroid.y(), radius);
  std::printf("kincal %s: a circle through %zu points, from (%.3f, %.3f, %.3f)\n",
              KINCAL_VERSION_STRING, points.size(), start.x(), start.y(), start.z());

  int failures = 0;
  const SolverRegistry& registry = SolverRegistry::global();
  for (const auto& info : registry.list()) {
    for (const std::string& name : info.variants) {
      VectorXd x = start;
      SolverOptions options;
      options.max_iterations = 500;
      const Summary summary = registry.create(name)->solve(problem, x, options);
      const double error = (x - circle).cwiseAbs().maxCoeff();
      bool ok;
      if (info.kind == SolverKind::kLeastSquares)
        ok = summary.converged() && error < 1e-6;
      else
        ok = summary.final_cost < summary.initial_cost &&
             (!summary.converged() || summary.final_cost < 1e-8);
      failures += !ok;
      std::printf("%-32s %-14s cost %.2e -> %.2e, %3d iterations, max error %.1e %s\n",
                  name.c_str(), to_string(summary.termination), summary.initial_cost,
                  summary.final_cost, summary.iterations, error, ok ? "" : " <- FAILED");
    }
  }
  for (const auto& missing : registry.unavailable())
    std::printf("%-32s not in this build: %s\n", missing.name.c_str(), missing.reason.c_str());
  return failures == 0 ? 0 : 1;
}
