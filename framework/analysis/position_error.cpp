#include "kincal/framework/analysis/position_error.hpp"

#include <algorithm>
#include <cmath>
#include <stdexcept>

#include "kincal/framework/analysis/pose_accuracy.hpp"

namespace kincal {

bool measures_position(const MeasurementModel& model) {
  for (const auto& sensor : model.sensors())
    if (sensor->position_reading_index() >= 0) return true;
  return false;
}

MatrixXd residual_matrix(const CalibrationProblem& problem, const VectorXd& x) {
  const MeasurementModel& model = problem.model();
  const Measurements& data = problem.data();
  const int k = model.num_readings();
  VectorXd r;
  std::string why;
  if (!problem.evaluate(x, &r, nullptr, &why)) throw std::runtime_error(why);
  MatrixXd out(data.size(), k);
  for (int c = 0; c < data.size(); ++c)
    for (int i = 0; i < k; ++i)
      out(c, i) = std::isnan(data.readings(c, i)) ? NAN : r[c * k + i] * model.reading_std()[i];
  return out;
}

MatrixXd residual_matrix(std::shared_ptr<const MeasurementModel> model, const Measurements& data,
                         const VectorXd& values) {
  const CalibrationProblem problem(std::move(model), data, values, {});
  return residual_matrix(problem, problem.initial_free_parameters());
}

std::map<std::string, double> residual_rms_by_unit(const MeasurementModel& model,
                                                   const MatrixXd& residuals) {
  std::map<std::string, double> sum;
  std::map<std::string, int> count;
  const auto units = model.reading_units();
  for (int c = 0; c < residuals.rows(); ++c)
    for (int i = 0; i < residuals.cols(); ++i)
      if (!std::isnan(residuals(c, i))) {
        sum[units[i]] += residuals(c, i) * residuals(c, i);
        ++count[units[i]];
      }
  for (auto& [unit, value] : sum) value = std::sqrt(value / count[unit]);
  return sum;
}

std::vector<double> position_errors(const MeasurementModel& model, const MatrixXd& residuals) {
  std::vector<double> errors;
  for (int c = 0; c < residuals.rows(); ++c)
    for (std::size_t s = 0; s < model.sensors().size(); ++s) {
      const int index = model.sensors()[s]->position_reading_index();
      if (index < 0) continue;
      const int o = model.sensor_reading_offset(static_cast<int>(s)) + index;
      const Vector3d e = residuals.row(c).segment<3>(o).transpose();
      if (e.array().isNaN().any()) continue;  // not measured
      errors.push_back(e.norm());
    }
  return errors;
}

PositionErrorStats summarize_position_errors(const std::vector<double>& errors) {
  PositionErrorStats s;
  s.points = static_cast<int>(errors.size());
  if (errors.empty()) return s;
  double sum = 0, squares = 0, max = 0;
  for (double e : errors) {
    sum += e;
    squares += e * e;
    max = std::max(max, e);
  }
  s.mean = sum / s.points;
  s.rms = std::sqrt(squares / s.points);
  s.max = max;
  return s;
}

namespace {

nlohmann::ordered_json number(double v) {
  return std::isfinite(v) ? nlohmann::ordered_json(v) : nlohmann::ordered_json();
}

}  // namespace

nlohmann::ordered_json to_json(const PositionErrorStats& s) {
  return {{"points", s.points},
          {"mean", number(s.mean)},
          {"rms", number(s.rms)},
          {"max", number(s.max)}};
}

PointErrorPrediction predict_point_errors(const CalibrationProblem& problem, const VectorXd& x,
                                          const MatrixXd& covariance) {
  PointErrorPrediction p;
  const MeasurementModel& model = problem.model();
  const int n = problem.num_parameters();
  if (!measures_position(model) || covariance.rows() != n || covariance.cols() != n ||
      !covariance.allFinite())
    return p;
  VectorXd r;
  MatrixXd J;
  if (!problem.evaluate(x, &r, &J)) return p;
  const int k = model.num_readings();
  const Measurements& data = problem.data();
  double sum_trace = 0, sum_1 = 0, sum_95 = 0, max_1 = 0, max_95 = 0;
  for (int c = 0; c < data.size(); ++c)
    for (std::size_t s = 0; s < model.sensors().size(); ++s) {
      const int index = model.sensors()[s]->position_reading_index();
      if (index < 0) continue;
      const int o = model.sensor_reading_offset(static_cast<int>(s)) + index;
      if (data.readings.row(c).segment(o, 3).array().isNaN().any()) continue;
      Eigen::Matrix<double, 3, Eigen::Dynamic> Jp = J.middleRows(c * k + o, 3);
      for (int i = 0; i < 3; ++i) Jp.row(i) *= model.reading_std()[o + i];  // back to mm
      const Matrix3d cov = Jp * covariance * Jp.transpose();
      const double trace = std::max(cov.trace(), 0.0);
      const double q95 = error_norm_quantile(cov, 0.95);
      sum_trace += trace;
      sum_1 += std::sqrt(trace);
      sum_95 += q95;
      max_1 = std::max(max_1, std::sqrt(trace));
      max_95 = std::max(max_95, q95);
      ++p.points;
    }
  if (p.points == 0) return p;
  p.rms = std::sqrt(sum_trace / p.points);
  p.mean_1sigma = sum_1 / p.points;
  p.max_1sigma = max_1;
  p.mean_95 = sum_95 / p.points;
  p.max_95 = max_95;
  return p;
}

nlohmann::ordered_json to_json(const PointErrorPrediction& p) {
  return {{"points", p.points},
          {"rms", number(p.rms)},
          {"mean_1sigma", number(p.mean_1sigma)},
          {"max_1sigma", number(p.max_1sigma)},
          {"mean_95", number(p.mean_95)},
          {"max_95", number(p.max_95)}};
}

std::vector<int> registration_indices(const MeasurementModel& model, const std::vector<int>& free) {
  const int n_mech = model.mechanism().num_parameters();
  std::vector<int> out;
  for (int i : free) {
    const std::string& name = model.parameters()[i].name;
    if (i >= n_mech || name.rfind("base.", 0) == 0 || name.rfind("tool.", 0) == 0) out.push_back(i);
  }
  return out;
}

std::vector<int> measured_point_indices(const MeasurementModel& model,
                                        const std::vector<int>& free) {
  std::vector<int> out;
  for (int i : registration_indices(model, free)) {
    const std::string& name = model.parameters()[i].name;
    const std::string axis = name.substr(name.rfind('.') + 1);
    if (axis != "x" && axis != "y" && axis != "z") continue;
    if (name.rfind("tool.", 0) == 0 || name.find(".target.") != std::string::npos ||
        name.find(".marker.") != std::string::npos)
      out.push_back(i);
  }
  return out;
}

}  // namespace kincal
