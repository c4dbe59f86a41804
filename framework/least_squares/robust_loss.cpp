#include "kincal/framework/least_squares/robust_loss.hpp"

#include <cmath>
#include <sstream>
#include <stdexcept>

namespace kincal {

RobustLoss RobustLoss::parse(const std::string& text) {
  RobustLoss loss;
  if (text.empty() || text == "none") return loss;
  const auto colon = text.find(':');
  const std::string kind = text.substr(0, colon);
  if (kind == "huber") {
    loss.kind = Kind::kHuber;
  } else if (kind == "cauchy") {
    loss.kind = Kind::kCauchy;
  } else {
    throw std::invalid_argument("loss '" + text +
                                "': expected none, huber:<delta> or cauchy:<delta>");
  }
  std::istringstream in(colon == std::string::npos ? "" : text.substr(colon + 1));
  if (!(in >> loss.delta) || !(in >> std::ws).eof() || !(loss.delta > 0) ||
      !std::isfinite(loss.delta))
    throw std::invalid_argument("loss '" + text + "': delta must be a positive number");
  return loss;
}

std::string RobustLoss::to_string() const {
  std::ostringstream out;
  switch (kind) {
    case Kind::kNone:
      return "none";
    case Kind::kHuber:
      out << "huber:" << delta;
      break;
    case Kind::kCauchy:
      out << "cauchy:" << delta;
      break;
  }
  return out.str();
}

std::array<double, 3> RobustLoss::evaluate(double s) const {
  const double d2 = delta * delta;
  switch (kind) {
    case Kind::kNone:
      return {s, 1.0, 0.0};
    case Kind::kHuber: {
      if (s <= d2) return {s, 1.0, 0.0};
      const double r = std::sqrt(s);
      return {2.0 * delta * r - d2, delta / r, -0.5 * delta / (s * r)};
    }
    case Kind::kCauchy: {
      const double inv = 1.0 / (1.0 + s / d2);
      return {d2 * std::log1p(s / d2), inv, -inv * inv / d2};
    }
  }
  return {s, 1.0, 0.0};
}

double RobustLoss::cost(const VectorXd& r) const {
  if (kind == Kind::kNone) return 0.5 * r.squaredNorm();
  double sum = 0;
  for (Eigen::Index i = 0; i < r.size(); ++i) sum += evaluate(r[i] * r[i])[0];
  return 0.5 * sum;
}

void RobustLoss::correct(VectorXd& r, MatrixXd& J, VectorXd& row_scale) const {
  if (kind == Kind::kNone) {
    row_scale.setOnes();
    return;
  }
  for (Eigen::Index i = 0; i < r.size(); ++i) {
    const double s = r[i] * r[i];
    const auto rho = evaluate(s);
    const double sqrt_rho1 = std::sqrt(rho[1]);
    double residual_scale = sqrt_rho1, jacobian_scale = sqrt_rho1;
    if (s > 0 && rho[2] > 0) {
      const double alpha = 1.0 - std::sqrt(1.0 + 2.0 * s * rho[2] / rho[1]);
      residual_scale = sqrt_rho1 / (1.0 - alpha);
      jacobian_scale = sqrt_rho1 * (1.0 - alpha);
    }
    r[i] *= residual_scale;
    J.row(i) *= jacobian_scale;
    row_scale[i] = jacobian_scale;
  }
}

}  // namespace kincal
