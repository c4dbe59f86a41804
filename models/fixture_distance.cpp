#include "kincal/models/fixture_distance.hpp"

#include <cmath>
#include <cstdio>
#include <stdexcept>

#include "kincal/framework/kinematics/units.hpp"

namespace kincal {

std::vector<std::string> fixture_point_names(const std::string& sensor) {
  return {sensor + ".point.x", sensor + ".point.y", sensor + ".point.z"};
}

FixtureDistance::FixtureDistance(std::string a, std::string b, double distance, double std)
    : a_(std::move(a)), b_(std::move(b)), distance_(distance), std_(std) {
  if (a_ == b_)
    throw std::invalid_argument("expected two different sensors, got '" + a_ + "' twice");
  if (!(std::isfinite(distance_) && distance_ >= 0))
    throw std::invalid_argument("expected a distance >= 0 (mm)");
  if (!(std::isfinite(std_) && std_ > 0)) throw std::invalid_argument("expected a std > 0 (mm)");
  names_ = fixture_point_names(a_);
  for (const auto& name : fixture_point_names(b_)) names_.push_back(name);
}

std::string FixtureDistance::label() const {
  char d[64];
  std::snprintf(d, sizeof d, "%g", distance_);
  return "|" + a_ + " - " + b_ + "| = " + d + " mm";
}

std::vector<std::string> FixtureDistance::residual_units() const { return {kMillimetre}; }

void FixtureDistance::evaluate(const Eigen::Ref<const VectorXd>& values,
                               Eigen::Ref<VectorXd> residuals, MatrixXd* J) const {
  const Vector3d v = values.segment<3>(0) - values.segment<3>(3);
  const double length = v.norm();
  residuals[0] = length - distance_;
  if (J) {
    const Vector3d u = length > 0 ? Vector3d(v / length) : Vector3d::Zero();
    J->block<1, 3>(0, 0) = u.transpose();
    J->block<1, 3>(0, 3) = -u.transpose();
  }
}

}  // namespace kincal
