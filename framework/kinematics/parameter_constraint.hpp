#pragma once
// A residual on a model's parameters alone, not on a configuration: what is known about the
// unknowns the sensors own (the distance between two fixture points, with its uncertainty).
// A model holds its constraints beside its sensors (MeasurementModel::constraints, the model
// file's "constraints"); a calibration adds each constraint's residuals once, divided by
// their std, to the least-squares problem (framework/calibration/constrained_problem.hpp), so that
// they count in the cost, the Jacobian, the covariance and the identifiability like readings. A new
// kind is a class deriving from this and a ConstraintType registered beside the sensor types
// (framework/extension/model_registry.hpp); models/fixture_distance.* is the example.

#include <string>
#include <vector>

#include "kincal/framework/base/types.hpp"

namespace kincal {

class ParameterConstraint {
 public:
  virtual ~ParameterConstraint() = default;

  /// Type as written in model files, e.g. "fixture-distance".
  virtual std::string type() const = 0;
  /// What it constrains, in reports, e.g. "|socket0 - socket1| = 50 mm".
  virtual std::string label() const = 0;
  /// The model parameters it reads, by name, in the order evaluate() takes their values.
  virtual const std::vector<std::string>& parameter_names() const = 0;
  virtual int num_residuals() const = 0;
  /// Unit of each residual ("mm", "rad").
  virtual std::vector<std::string> residual_units() const = 0;
  /// Standard deviation of each residual (its unit), > 0: the residuals are divided by it.
  virtual VectorXd residual_std() const = 0;
  /// The residuals (unweighted, in their units) at `values` and, when J is non-null, their
  /// Jacobian (num_residuals x parameter_names().size(), presized).
  virtual void evaluate(const Eigen::Ref<const VectorXd>& values, Eigen::Ref<VectorXd> residuals,
                        MatrixXd* J) const = 0;
};

}  // namespace kincal
