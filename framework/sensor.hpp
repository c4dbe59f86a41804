#pragma once
// The Sensor interface: what an external sensor reads when the mechanism is at a pose.

#include <string>
#include <vector>

#include "kincal/framework/parameters.hpp"
#include "kincal/framework/pose.hpp"

namespace kincal {

class Sensor {
 public:
  virtual ~Sensor() = default;

  /// Sensor type as written in model files, e.g. "length-gauge".
  virtual std::string type() const = 0;
  /// Name of the sensor; also its column name in measurement files ("gauge").
  virtual const std::string& name() const = 0;
  /// Number of scalar readings per configuration (1 for a length gauge).
  virtual int num_readings() const = 0;
  /// Column names of the readings (num_readings() of them).
  virtual std::vector<std::string> reading_names() const { return {name()}; }
  /// Parameter layout with nominal values and the default free mask.
  virtual const std::vector<Parameter>& parameters() const = 0;
  int num_parameters() const { return static_cast<int>(parameters().size()); }

  /// Readings at `pose` and, when the pointers are non-null, J_reading_pose
  /// (num_readings x 6) and J_reading_params (num_readings x num_parameters), each presized
  /// by the caller so that no allocation happens here.
  virtual void predict(const Eigen::Ref<const VectorXd>& params, const Pose& pose,
                       Eigen::Ref<VectorXd> reading, MatrixXd* J_reading_pose,
                       MatrixXd* J_reading_params) const = 0;
};

}  // namespace kincal
