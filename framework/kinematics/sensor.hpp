#pragma once
// The Sensor interface: what an external sensor reads when the mechanism is at a pose.

#include <functional>
#include <string>
#include <vector>

#include "kincal/framework/kinematics/parameters.hpp"
#include "kincal/framework/kinematics/pose.hpp"

namespace kincal {

/// Another way a measurement file may give some of a sensor's readings: an orientation as
/// roll-pitch-yaw angles or a quaternion where the readings are a rotation vector. Its columns
/// are read instead of those readings and converted row by row on reading, so that the
/// convention is stated by the columns' names and never guessed from their values.
struct ReadingColumns {
  std::string convention;  ///< in words, for messages: "roll-pitch-yaw"
  int first_reading = 0;   ///< the sensor's readings it gives: first_reading, ... + readings - 1
  int readings = 0;
  std::vector<std::string> columns;  ///< full column names, e.g. "tracker.roll"
  /// Per column: "rad" (an angle: a _deg or _rad suffix converts it) or "" (a plain number,
  /// which takes no unit suffix).
  std::vector<std::string> units;
  /// The readings from one row's column values (in `units`); false with a reason when the
  /// values are not a valid instance of the convention (a quaternion far from unit length).
  std::function<bool(const double* columns, double* readings, std::string* why)> convert;
};

/// Column names a measurement file may not use for a sensor because they do not say what
/// they hold, with why and what to name them instead (e.g. "tracker.rx" could be a rotation
/// vector or Euler angles). A unit suffix does not lift the refusal.
struct RefusedColumns {
  std::vector<std::string> columns;
  std::string why;
};

class Sensor {
 public:
  virtual ~Sensor() = default;

  /// Sensor type as written in model files, e.g. "length-gauge".
  virtual std::string type() const = 0;
  /// Name of the sensor: the prefix of its parameter names and reading columns.
  virtual const std::string& name() const = 0;
  /// Number of scalar readings per configuration (1 for a length gauge).
  virtual int num_readings() const = 0;
  /// Column names of the readings in measurement files (num_readings() of them).
  virtual std::vector<std::string> reading_names() const { return {name()}; }
  /// Other columns a measurement file may give some readings in (converted on reading), and
  /// names it may not use. Default: none; the readings' own names only.
  virtual std::vector<ReadingColumns> alternative_columns() const { return {}; }
  virtual std::vector<RefusedColumns> refused_columns() const { return {}; }
  /// Unit of each reading ("mm" or "rad"), in reading_names() order.
  virtual std::vector<std::string> reading_units() const = 0;
  /// Index of the first of three readings that are the measured point's position (x, y, z in
  /// mm, in the sensor's own Cartesian frame), or -1 when the sensor measures no point (a
  /// length gauge). Accuracy in the field's terms (3-D position error) is computed from them.
  virtual int position_reading_index() const { return -1; }
  /// Index of the first of three readings that are the measured frame's orientation as a
  /// rotation vector (axis times angle, rad, in the sensor's frame), or -1 (the default) when
  /// the sensor measures no orientation. ISO 9283's orientation statistics come from them.
  virtual int orientation_reading_index() const { return -1; }
  /// Index of the first of three readings that are a vector in the measurement frame itself
  /// (the frame the mechanism's base and the sensors' own placements are given in), or -1
  /// (the default) for readings in a frame of the sensor's own (a tracker's) or no vector at
  /// all (a length). Turning the whole setup by R turns such readings by R; measured as 0 (a
  /// socket's: the tool point minus the socket's centre), they then leave the cost as it is,
  /// so nothing measured fixes the frame's orientation: a gauge freedom that the Jacobian
  /// does not show as a null direction (framework/calibration/frame_turns.hpp).
  virtual int frame_vector_reading_index() const { return -1; }
  /// Parameter layout with nominal values and units; all fixed (a model's mask frees them).
  virtual const std::vector<Parameter>& parameters() const = 0;
  int num_parameters() const { return static_cast<int>(parameters().size()); }

  /// Readings at `pose` and, when the pointers are non-null, J_reading_pose
  /// (num_readings x 6) and J_reading_params (num_readings x num_parameters), each presized
  /// by the caller so that no allocation happens here. For readings that live on a manifold
  /// (a rotation), the Jacobian rows are taken in its tangent space, the space of
  /// reading_error() (see PoseTracker).
  virtual void predict(const Eigen::Ref<const VectorXd>& params, const Pose& pose,
                       Eigen::Ref<VectorXd> reading, MatrixXd* J_reading_pose,
                       MatrixXd* J_reading_params) const = 0;

  /// How many consecutive readings are taken or missed together: a measurement file gives
  /// each group of this many whole or leaves it empty (a camera's u and v of one target point:
  /// 2, each point detected or not). Default: every reading of the sensor, one group.
  virtual int reading_group_size() const { return num_readings(); }
  /// Whether `value`, measured for reading `index`, can be a reading of this sensor at all;
  /// when not, a short reason in `reason` (when non-null), e.g. "u = 700 px is outside the
  /// 640 px wide image". A measurement file with such a value is refused with its line.
  /// Default: any finite value.
  virtual bool valid_reading(int index, double value, std::string* reason) const;

  /// Whether a calibration with this sensor takes priors from the model's stated tolerances
  /// unless told otherwise (CalibrateRequest::tolerance_priors): true for a sensor whose own
  /// parameters trade with the mechanism's, so that a fit can lower its residuals by moving
  /// a good geometry to absorb the sensor's errors (a camera: its intrinsics and mounts against
  /// the robot's joint offsets; issue 38). Default: false.
  virtual bool takes_tolerance_priors_by_default() const { return false; }

  /// Whether the sensor can fail to read at some poses (a beam grazing or missing its
  /// target, a reading out of range). Only then is reads_at() called, so sensors that always
  /// read cost nothing.
  virtual bool can_miss() const { return false; }
  /// Whether the sensor gives a reading at `pose`; when not, a short reason without the
  /// sensor's name in `reason` (when non-null), e.g. "beam misses the plane". A reading the
  /// sensor cannot take is dropped for that configuration, like an unmeasured one (NaN in
  /// the predicted readings; see MeasurementModel::predict), and reported when data are read
  /// (find_missed_readings in measurement_file.hpp). Default: always.
  virtual bool reads_at(const Eigen::Ref<const VectorXd>& params, const Pose& pose,
                        std::string* reason) const;

  /// For simulated measurements: the readings a sensor that can miss would not take at `pose`
  /// although it reads there (a camera's target points outside its image or seen edge-on), set
  /// to NaN in `reading` (its predicted readings); returns how many. Only called when
  /// can_miss() and reads_at(). Default: none.
  virtual int drop_unseen(const Eigen::Ref<const VectorXd>& params, const Pose& pose,
                          Eigen::Ref<VectorXd> reading) const;

  /// Whether reading_error() is more than predicted - measured. Only then is it called with
  /// a Jacobian, so plain sensors cost nothing.
  virtual bool has_manifold_readings() const { return false; }
  /// The residual of a predicted reading against a measured one and, when asked for,
  /// J_error_predicted (num_readings x num_readings): how the error moves with the
  /// predicted reading's tangent perturbation. Default: predicted - measured, identity.
  virtual void reading_error(const Eigen::Ref<const VectorXd>& predicted,
                             const Eigen::Ref<const VectorXd>& measured, Eigen::Ref<VectorXd> error,
                             MatrixXd* J_error_predicted) const;
  /// `reading` moved by the tangent perturbation `delta`, the inverse of reading_error:
  /// reading_error(retract(m, d), m) = d. Default: reading + delta. Simulation adds noise
  /// through it.
  virtual void retract(Eigen::Ref<VectorXd> reading, const Eigen::Ref<const VectorXd>& delta) const;
};

}  // namespace kincal
