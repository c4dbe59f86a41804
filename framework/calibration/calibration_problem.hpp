#pragma once
// The identification problem as a generic least-squares problem:
//   x = the free parameters, residual_j = (predicted readings(q_j) - measured readings_j) / std,
// with std the model's reading_std() (1 unless the model states the readings' noise), and
// the difference taken by each sensor's reading_error (a rotation error for rotations).

#include <cstdint>
#include <memory>
#include <vector>

#include "kincal/framework/kinematics/measurement_model.hpp"
#include "kincal/framework/least_squares/least_squares_problem.hpp"

namespace kincal {

/// Measured configurations: row j holds the actuator values and the sensor readings of
/// configuration j, in the model's actuator and reading order. A reading the sensor did not
/// take is NaN (an empty field in a measurement file): it contributes no residual.
struct Measurements {
  MatrixXd actuators;  ///< m x num_actuators
  MatrixXd readings;   ///< m x num_readings
  int size() const { return static_cast<int>(actuators.rows()); }
  /// Readings present (not NaN), in all and per column.
  int num_present() const;
  /// The residual rows (configuration c, reading i: c * num_readings + i) of the readings
  /// present, in order: what an analysis of the Jacobian should see (a missing reading is a
  /// fixed zero row).
  std::vector<int> present_rows() const;
  Eigen::VectorXi present_per_column() const;
};

class CalibrationProblem : public LeastSquaresProblem {
 public:
  /// `parameters` holds the values of every parameter (fixed ones stay at these values);
  /// `free_indices` selects the estimated ones, in that order.
  CalibrationProblem(std::shared_ptr<const MeasurementModel> model, Measurements data,
                     VectorXd parameters, std::vector<int> free_indices);

  int num_parameters() const override { return static_cast<int>(free_indices_.size()); }
  int num_residual_blocks() const override { return data_.size(); }
  int residuals_per_block() const override { return model_->num_readings(); }
  std::vector<std::string> parameter_names() const override;

  bool evaluate_block(int block, const VectorXd& x, Eigen::Ref<VectorXd> residuals,
                      Eigen::Ref<MatrixXd>* jacobian, std::string* why) const override;
  /// For a mechanism whose forward kinematics iterates (a closed chain): each
  /// configuration's pose at the last evaluation where forward kinematics converged, from
  /// which the next starts instead of from the home pose. Null for the others.
  std::unique_ptr<WarmStart> make_warm_start() const override;
  /// The same, with configuration j starting from poses[j] (one per configuration): poses
  /// already closed, as the implicit formulation's, leave its forward kinematics one step.
  std::unique_ptr<WarmStart> make_warm_start(const std::vector<Pose>& poses) const;
  /// evaluate_block with forward kinematics from the configuration's last pose in `warm`;
  /// where that fails, from the home pose again, so a warm start never fails an evaluation
  /// the home pose would not.
  bool evaluate_block_warm(int block, const VectorXd& x, Eigen::Ref<VectorXd> residuals,
                           Eigen::Ref<MatrixXd>* jacobian, std::string* why,
                           WarmStart& warm) const override;

  /// Full parameter vector with the free entries taken from x.
  VectorXd full_parameters(const VectorXd& x) const;
  /// Free entries of a full parameter vector.
  VectorXd free_parameters(const VectorXd& full) const;
  /// x at the base parameter values.
  VectorXd initial_free_parameters() const { return free_parameters(base_); }

  /// Residuals that carry a measured reading (missing readings give fixed zeros).
  int num_measured_residuals() const { return data_.num_present(); }

  const MeasurementModel& model() const { return *model_; }
  const std::shared_ptr<const MeasurementModel>& model_ptr() const { return model_; }
  const Measurements& data() const { return data_; }
  const std::vector<int>& free_indices() const { return free_indices_; }

 private:
  struct LastPoses;
  bool evaluate_block_from(int block, const VectorXd& x, Eigen::Ref<VectorXd> residuals,
                           Eigen::Ref<MatrixXd>* jacobian, std::string* why, LastPoses* last) const;

  std::shared_ptr<const MeasurementModel> model_;
  Measurements data_;
  VectorXd base_;
  std::vector<int> free_indices_;
  bool weighted_ = false;
  /// Tells per-thread scratch built for this problem's base_ and free_indices_ (which never
  /// change after construction) from scratch built for another problem.
  std::uint64_t scratch_key_ = 0;
};

}  // namespace kincal
