#include "kincal/framework/calibration/calibration_problem.hpp"

#include <atomic>
#include <cmath>
#include <cstring>
#include <stdexcept>

namespace kincal {

int Measurements::num_present() const {
  return static_cast<int>((readings.array() == readings.array()).count());
}

std::vector<int> Measurements::present_rows() const {
  std::vector<int> rows;
  rows.reserve(static_cast<std::size_t>(num_present()));
  const Eigen::Index k = readings.cols();
  for (Eigen::Index c = 0; c < readings.rows(); ++c)
    for (Eigen::Index i = 0; i < k; ++i)
      if (!std::isnan(readings(c, i))) rows.push_back(static_cast<int>(c * k + i));
  return rows;
}

Eigen::VectorXi Measurements::present_per_column() const {
  Eigen::VectorXi counts(readings.cols());
  for (Eigen::Index c = 0; c < readings.cols(); ++c)
    counts[c] = static_cast<int>((readings.col(c).array() == readings.col(c).array()).count());
  return counts;
}

CalibrationProblem::CalibrationProblem(std::shared_ptr<const MeasurementModel> model,
                                       Measurements data, VectorXd parameters,
                                       std::vector<int> free_indices)
    : model_(std::move(model)),
      data_(std::move(data)),
      base_(std::move(parameters)),
      free_indices_(std::move(free_indices)) {
  if (base_.size() != model_->num_parameters())
    throw std::invalid_argument("parameter vector has " + std::to_string(base_.size()) +
                                " entries, the model has " +
                                std::to_string(model_->num_parameters()));
  if (data_.actuators.cols() != model_->mechanism().num_actuators() ||
      data_.readings.cols() != model_->num_readings() ||
      data_.actuators.rows() != data_.readings.rows())
    throw std::invalid_argument("measurements do not match the model's actuators and sensors");
  for (int i : free_indices_)
    if (i < 0 || i >= base_.size()) throw std::invalid_argument("free index out of range");
  weighted_ = model_->weighted();
  static std::atomic<std::uint64_t> next_scratch_key{1};
  scratch_key_ = next_scratch_key++;
}

std::vector<std::string> CalibrationProblem::parameter_names() const {
  std::vector<std::string> names;
  for (int i : free_indices_) names.push_back(model_->parameters()[i].name);
  return names;
}

VectorXd CalibrationProblem::full_parameters(const VectorXd& x) const {
  VectorXd full = base_;
  for (std::size_t i = 0; i < free_indices_.size(); ++i) full[free_indices_[i]] = x[i];
  return full;
}

VectorXd CalibrationProblem::free_parameters(const VectorXd& full) const {
  VectorXd x(free_indices_.size());
  for (std::size_t i = 0; i < free_indices_.size(); ++i) x[i] = full[free_indices_[i]];
  return x;
}

namespace {

// Per-thread scratch so that evaluate_block allocates nothing once warmed up.
struct BlockScratch {
  VectorXd full;  // the full parameter vector of `full_x` for problem `full_key`
  VectorXd full_x;
  std::uint64_t full_key = 0;
  VectorXd predicted;
  VectorXd measured;
  MatrixXd J_full;
  MeasurementModel::Workspace model;
};

// Newton steps forward kinematics may take from a warm start before it starts again from
// home: from the pose of a nearby parameter vector it converges in one to three.
constexpr int kWarmStartNewtonSteps = 3;

}  // namespace

struct CalibrationProblem::LastPoses : WarmStart {
  std::vector<Pose> poses;
  std::vector<char> known;  // not bool: blocks on different threads write neighbouring entries
};

std::unique_ptr<WarmStart> CalibrationProblem::make_warm_start() const {
  if (!model_->mechanism().forward_kinematics_has_assemblies()) return nullptr;
  auto last = std::make_unique<LastPoses>();
  last->poses.assign(static_cast<std::size_t>(data_.size()), model_->mechanism().home_pose());
  last->known.assign(static_cast<std::size_t>(data_.size()), 0);
  return last;
}

std::unique_ptr<WarmStart> CalibrationProblem::make_warm_start(
    const std::vector<Pose>& poses) const {
  if (poses.size() != static_cast<std::size_t>(data_.size()))
    throw std::invalid_argument(
        "CalibrationProblem::make_warm_start: " + std::to_string(poses.size()) + " poses for " +
        std::to_string(data_.size()) + " configurations");
  if (!model_->mechanism().forward_kinematics_has_assemblies()) return nullptr;
  auto last = std::make_unique<LastPoses>();
  last->poses = poses;
  last->known.assign(poses.size(), 1);
  return last;
}

bool CalibrationProblem::evaluate_block(int block, const VectorXd& x,
                                        Eigen::Ref<VectorXd> residuals,
                                        Eigen::Ref<MatrixXd>* jacobian, std::string* why) const {
  return evaluate_block_from(block, x, residuals, jacobian, why, nullptr);
}

bool CalibrationProblem::evaluate_block_warm(int block, const VectorXd& x,
                                             Eigen::Ref<VectorXd> residuals,
                                             Eigen::Ref<MatrixXd>* jacobian, std::string* why,
                                             WarmStart& warm) const {
  return evaluate_block_from(block, x, residuals, jacobian, why, dynamic_cast<LastPoses*>(&warm));
}

bool CalibrationProblem::evaluate_block_from(int block, const VectorXd& x,
                                             Eigen::Ref<VectorXd> residuals,
                                             Eigen::Ref<MatrixXd>* jacobian, std::string* why,
                                             LastPoses* last) const {
  thread_local BlockScratch scratch;
  const int k = model_->num_readings();
  // A contiguous copy: a row of the column-major readings would be heap-copied to bind to the
  // model's Ref<const VectorXd> on every call.
  scratch.measured = data_.readings.row(block).transpose();
  if (scratch.measured.array().isNaN().all()) {
    // Nothing was measured here: no residual, and no need to reach the configuration.
    residuals.setZero();
    if (jacobian) jacobian->setZero();
    return true;
  }
  // The full vector depends on x alone: built once per thread and evaluation, not once per
  // configuration (the copy and scatter were 3 % of a calibration).
  // (Compared bit for bit: -0.0 == 0.0, and NaN != NaN.)
  if (scratch.full_key != scratch_key_ || scratch.full_x.size() != x.size() ||
      (x.size() > 0 &&
       std::memcmp(scratch.full_x.data(), x.data(), sizeof(double) * x.size()) != 0)) {
    scratch.full = base_;  // same sizes every call: no reallocation
    for (std::size_t i = 0; i < free_indices_.size(); ++i) scratch.full[free_indices_[i]] = x[i];
    scratch.full_x = x;
    scratch.full_key = scratch_key_;
  }
  scratch.predicted.resize(k);
  if (jacobian) scratch.J_full.resize(k, base_.size());
  Eigen::Ref<MatrixXd> J_ref(scratch.J_full);
  // Warm: from the configuration's last pose, in the few Newton steps that stay on its
  // assembly (a step of the parameters that moves the pose further, as a line search's wild
  // probe can, could carry it onto another); otherwise, or if that fails, from home.
  const auto j = static_cast<std::size_t>(block);
  const bool warm = last && last->known[j];
  ForwardKinematicsResult fk =
      model_->predict(scratch.full, data_.actuators.row(block).transpose(), scratch.predicted,
                      jacobian ? &J_ref : nullptr, scratch.model, warm ? &last->poses[j] : nullptr,
                      warm ? kWarmStartNewtonSteps : -1);
  if (warm && !fk.ok())
    fk = model_->predict(scratch.full, data_.actuators.row(block).transpose(), scratch.predicted,
                         jacobian ? &J_ref : nullptr, scratch.model);
  if (last && fk.ok()) {
    last->poses[j] = fk.pose;
    last->known[j] = 1;
  }
  if (!fk.ok()) {
    if (why)
      *why = "configuration " + std::to_string(block + 1) + ": forward kinematics " + fk.describe();
    return false;
  }
  if (model_->sensors_can_miss()) {
    // A measured reading that the sensor cannot take at x fails the evaluation, as forward
    // kinematics does: dropping it instead would let the solver lower the cost by moving the
    // parameters until a sensor misses. Readings missed at the start were dropped from the
    // data when it was read (find_missed_readings).
    for (int i = 0; i < k; ++i) {
      if (!std::isnan(scratch.predicted[i]) || std::isnan(scratch.measured[i])) continue;
      if (why) {
        const int s = model_->sensor_of_reading(i);
        std::string reason;
        const Pose pose =
            model_->mechanism()
                .forward_kinematics(scratch.full.head(model_->mechanism().num_parameters()),
                                    data_.actuators.row(block).transpose(),
                                    model_->mechanism().home_pose(),
                                    model_->forward_kinematics_options())
                .pose;
        model_->sensor_reads_at(scratch.full, pose, s, &reason);
        *why = "configuration " + std::to_string(block + 1) + ": sensor " +
               model_->sensors()[s]->name() + ": no reading: " + reason;
      }
      return false;
    }
  }
  model_->reading_errors(scratch.predicted, scratch.measured, residuals,
                         jacobian ? &J_ref : nullptr);
  if (weighted_) {
    residuals.array() /= model_->reading_std().array();
    if (jacobian) scratch.J_full.array().colwise() /= model_->reading_std().array();
  }
  if (jacobian) {
    for (std::size_t i = 0; i < free_indices_.size(); ++i)
      jacobian->col(i) = scratch.J_full.col(free_indices_[i]);
  }
  return true;
}

}  // namespace kincal
