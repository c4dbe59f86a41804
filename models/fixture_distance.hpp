#pragma once
// A known distance between two sensors' fixture points (two sockets of one printed tool):
//   residual = |p_a - p_b| - d        (mm), weighted by 1 / std
// with p_a, p_b the sensors' parameters <name>.point.{x, y, z} (a socket's centre, mm).
// Socket data alone do not fix scale; this residual does. Added once to a calibration
// (framework/kinematics/parameter_constraint.hpp). Model file, in the top-level "constraints"
// array:
//   { "type": "fixture-distance", "between": ["socket0", "socket1"],
//     "distance": 50, "std": 0.05 }
// distance and std in mm. Where p_a = p_b the distance has no gradient; the Jacobian is then
// taken as zero (the residual is -d, which the data move away from).

#include <memory>

#include "kincal/framework/kinematics/parameter_constraint.hpp"

namespace kincal {

class ModelRegistry;

class FixtureDistance final : public ParameterConstraint {
 public:
  /// Between the fixture points of sensors `a` and `b`; throws std::invalid_argument when
  /// they are the same sensor, the distance is not finite and >= 0, or std is not finite and
  /// > 0.
  FixtureDistance(std::string a, std::string b, double distance, double std);

  std::string type() const override { return "fixture-distance"; }
  std::string label() const override;
  const std::vector<std::string>& parameter_names() const override { return names_; }
  int num_residuals() const override { return 1; }
  std::vector<std::string> residual_units() const override;
  VectorXd residual_std() const override { return VectorXd::Constant(1, std_); }
  void evaluate(const Eigen::Ref<const VectorXd>& values, Eigen::Ref<VectorXd> residuals,
                MatrixXd* J) const override;

  const std::string& a() const { return a_; }
  const std::string& b() const { return b_; }
  double distance() const { return distance_; }
  double std() const { return std_; }

 private:
  std::string a_, b_;
  double distance_, std_;
  std::vector<std::string> names_;
};

/// The parameter names of sensor `sensor`'s fixture point: <sensor>.point.{x, y, z}.
std::vector<std::string> fixture_point_names(const std::string& sensor);

/// Registers the constraint type (model-file reader/writer).
void register_fixture_distance(ModelRegistry& registry);

}  // namespace kincal
