#include "kincal/framework/workflows/compensate.hpp"

#include <Eigen/Cholesky>
#include <algorithm>
#include <cmath>
#include <cstdio>
#include <map>
#include <sstream>
#include <stdexcept>

#include "kincal/framework/calibration/measurement_file.hpp"

namespace kincal {

namespace {

bool has_column(const std::vector<std::string>& header, const std::string& name) {
  for (const std::string& field : header) {
    if (field == name) return true;
    for (const std::string& suffix : column_unit_suffixes())
      if (field == name + "_" + suffix) return true;
  }
  return false;
}

std::vector<int> commanded_actuators(const MeasurementModel& model) {
  std::vector<int> out;
  for (int a = 0; a < model.mechanism().num_actuators(); ++a)
    if (model.mechanism().actuators()[static_cast<std::size_t>(a)].commanded) out.push_back(a);
  return out;
}

std::string fmt(double v) {
  char buf[40];
  std::snprintf(buf, sizeof buf, "%.17g", v);
  return buf;
}

}  // namespace

CompensateTargets read_compensate_targets(
    const std::string& path, const MeasurementModel& model, const MeasurementModel* nominal,
    const VectorXd& near, const std::vector<std::pair<std::string, double>>& inputs) {
  const Mechanism& mechanism = model.mechanism();
  const int na = mechanism.num_actuators();
  const std::vector<std::string> actuators = mechanism.actuator_names();
  const std::vector<std::string> readings = model.reading_names();
  if (nominal) {
    if (nominal->mechanism().actuator_names() != actuators)
      throw std::invalid_argument("the nominal model's actuators differ from the model's");
    if (nominal->reading_names() != readings)
      throw std::invalid_argument("the nominal model's readings differ from the model's");
  }
  if (near.size() != 0 && near.size() != na)
    throw std::invalid_argument("the start configuration has " + std::to_string(near.size()) +
                                " values; the model has " + std::to_string(na) + " actuators");
  const CsvHeader header = read_csv_header(path);
  std::vector<std::string> present;
  int commanded_present = 0, commanded = 0;
  for (int a = 0; a < na; ++a) {
    const bool is_commanded = mechanism.actuators()[static_cast<std::size_t>(a)].commanded;
    commanded += is_commanded;
    if (has_column(header.fields, actuators[static_cast<std::size_t>(a)])) {
      present.push_back(actuators[static_cast<std::size_t>(a)]);
      commanded_present += is_commanded;
    }
  }
  if (commanded_present != 0 && commanded_present != commanded)
    throw std::invalid_argument(path + ":" + std::to_string(header.line) + ": " +
                                std::to_string(commanded_present) + " of the " +
                                std::to_string(commanded) +
                                " commanded actuator columns; give all of them or none");
  if (nominal && commanded_present == 0)
    throw std::invalid_argument(path + ":" + std::to_string(header.line) +
                                ": with a nominal model the file gives the commands (the "
                                "actuator columns) whose intended readings are wanted");
  MeasurementTable table =
      read_measurements(path, present, nominal ? std::vector<std::string>{} : readings);
  std::vector<std::string> present_units, reading_units = model.reading_units();
  for (const std::string& name : present)
    for (int a = 0; a < na; ++a)
      if (actuators[static_cast<std::size_t>(a)] == name)
        present_units.push_back(mechanism.actuators()[static_cast<std::size_t>(a)].unit);
  convert_column_units(table, present_units, nominal ? std::vector<std::string>{} : reading_units,
                       path);

  CompensateTargets t;
  const int rows = table.data.size();
  t.lines = table.line_numbers;
  t.starts_from_file = commanded_present > 0;
  VectorXd home(na);
  const VectorXd values = model.parameters().nominal_values();
  const InverseKinematicsResult h = mechanism.home_actuators(values, home);
  if (!h.ok()) throw std::invalid_argument("the model's home configuration: " + h.describe());
  const VectorXd start = near.size() == na ? near : home;
  t.starts.resize(rows, na);
  for (int r = 0; r < rows; ++r) t.starts.row(r) = start.transpose();
  for (const auto& [name, value] : inputs) {
    const auto it = std::find(actuators.begin(), actuators.end(), name);
    if (it == actuators.end())
      throw std::invalid_argument("no actuator '" + name + "' in the model");
    t.starts.col(it - actuators.begin()).setConstant(value);
  }
  for (std::size_t c = 0; c < present.size(); ++c) {
    const auto a = std::find(actuators.begin(), actuators.end(), present[c]) - actuators.begin();
    t.starts.col(a) = table.data.actuators.col(static_cast<Eigen::Index>(c));
  }
  if (nominal) {
    t.readings.resize(rows, model.num_readings());
    auto ws = nominal->make_workspace();
    const VectorXd nominal_values = nominal->parameters().nominal_values();
    VectorXd y(model.num_readings());
    for (int r = 0; r < rows; ++r) {
      const ForwardKinematicsResult fk =
          nominal->predict(nominal_values, t.starts.row(r).transpose(), y, nullptr, ws);
      if (!fk.ok() || y.hasNaN())
        throw std::invalid_argument(path + ":" +
                                    std::to_string(t.lines[static_cast<std::size_t>(r)]) +
                                    ": the nominal model reads nothing at these commands (" +
                                    (fk.ok() ? std::string("no reading") : fk.describe()) + ")");
      t.readings.row(r) = y.transpose();
    }
    t.readings_from = "the nominal model's readings at the file's commands";
  } else {
    t.readings = table.data.readings;
    for (int r = 0; r < rows; ++r)
      if (t.readings.row(r).hasNaN())
        throw std::invalid_argument(path + ":" +
                                    std::to_string(t.lines[static_cast<std::size_t>(r)]) +
                                    ": every wanted reading is needed (an empty field)");
    t.readings_from = "the file's reading columns";
  }
  return t;
}

namespace {

// One row: damped Gauss-Newton on the readings' error over the commanded actuators, the
// Jacobian by central differences of the model's predictions (the model's forward
// kinematics holds whatever the mechanism models, deflections included).
CompensatedRow solve_row(const MeasurementModel& model, const VectorXd& values,
                         const std::vector<int>& commanded, const VectorXd& start,
                         const VectorXd& wanted, double tolerance, int max_iterations,
                         MeasurementModel::Workspace& ws) {
  CompensatedRow row;
  row.start = start;
  row.wanted = wanted;
  const int k = model.num_readings(), n = static_cast<int>(commanded.size());
  VectorXd q = start, y(k), e(k), trial_e(k), y_plus(k), y_minus(k), e_plus(k), e_minus(k);
  const auto error_at = [&](const VectorXd& at, VectorXd& readings, VectorXd& error) {
    const ForwardKinematicsResult fk = model.predict(values, at, readings, nullptr, ws);
    if (!fk.ok() || readings.hasNaN()) return false;
    model.reading_errors(readings, wanted, error, nullptr);
    return error.allFinite();
  };
  if (!error_at(q, y, e)) {
    row.status = "unreachable";
    row.reason = "the model reads nothing at the start commands";
    row.commands = start;
    return row;
  }
  row.predicted_at_start = y;
  row.error_at_start = e.norm();
  MatrixXd J(k, n), A(n, n);
  VectorXd g(n), step(n);
  double lambda = 0;
  bool stuck = false;
  for (row.iterations = 0;
       row.iterations < max_iterations && e.lpNorm<Eigen::Infinity>() > tolerance;
       ++row.iterations) {
    for (int c = 0; c < n; ++c) {
      const int a = commanded[static_cast<std::size_t>(c)];
      const double h = 1e-6 * (1 + std::abs(q[a]));
      VectorXd plus = q, minus = q;
      plus[a] += h;
      minus[a] -= h;
      if (!error_at(plus, y_plus, e_plus) || !error_at(minus, y_minus, e_minus)) {
        stuck = true;
        break;
      }
      J.col(c) = (e_plus - e_minus) / (2 * h);
    }
    if (stuck) break;
    A.noalias() = J.transpose() * J;
    g.noalias() = J.transpose() * e;
    const double scale = A.diagonal().maxCoeff();
    // The error (nearly) orthogonal to every direction the commands move the readings: a
    // closest point, out of reach (or a singular configuration).
    if (!(scale > 0) || g.norm() <= 1e-6 * std::sqrt(A.trace()) * e.norm()) {
      stuck = true;
      break;
    }
    if (lambda == 0) lambda = 1e-9 * scale;
    bool accepted = false;
    while (!accepted && lambda < 1e6 * scale) {
      A.diagonal().array() += lambda;
      step = A.ldlt().solve(-g);
      A.diagonal().array() -= lambda;
      VectorXd trial = q;
      for (int c = 0; c < n; ++c) trial[commanded[static_cast<std::size_t>(c)]] += step[c];
      VectorXd trial_y(k);
      if (error_at(trial, trial_y, trial_e) && trial_e.squaredNorm() < e.squaredNorm()) {
        // A step that barely lowers the error: a closest point, not a solution.
        stuck = e.squaredNorm() - trial_e.squaredNorm() <= 1e-6 * e.squaredNorm();
        q = trial;
        y = trial_y;
        e = trial_e;
        lambda = std::max(lambda / 10, 1e-12 * scale);
        accepted = true;
      } else {
        lambda *= 10;
      }
    }
    if (!accepted) stuck = true;
    if (stuck) break;
  }
  row.commands = q;
  row.predicted = y;
  row.error = e.norm();
  if (e.lpNorm<Eigen::Infinity>() > tolerance) {
    char text[160];
    const auto units = model.reading_units();
    const std::string unit = units.empty() ? "" : " " + units.front();
    std::snprintf(text, sizeof text, "%s %.3g%s from the wanted readings after %d iterations%s",
                  stuck ? "stopped" : "still", row.error, unit.c_str(), row.iterations,
                  stuck ? " (a closest point: out of reach, or a singular configuration)" : "");
    row.status = stuck ? "unreachable" : "not_converged";
    row.reason = text;
  }
  return row;
}

}  // namespace

CompensateResult compensate(const CompensateRequest& request) {
  if (!request.model) throw std::invalid_argument("compensate: no model");
  const MeasurementModel& model = *request.model;
  const CompensateTargets& t = request.targets;
  if (t.readings.cols() != model.num_readings() ||
      t.starts.cols() != model.mechanism().num_actuators() || t.readings.rows() != t.starts.rows())
    throw std::invalid_argument("compensate: targets of the wrong shape for the model");
  const VectorXd values = model.parameters().nominal_values();
  const std::vector<int> commanded = commanded_actuators(model);
  auto ws = model.make_workspace();
  CompensateResult result;
  result.readings_from = t.readings_from;
  std::map<std::string, double> change;
  int solved = 0;
  for (Eigen::Index r = 0; r < t.readings.rows(); ++r) {
    CompensatedRow row =
        solve_row(model, values, commanded, t.starts.row(r).transpose(),
                  t.readings.row(r).transpose(), request.tolerance, request.max_iterations, ws);
    row.line = t.lines.empty() ? 0 : t.lines[static_cast<std::size_t>(r)];
    if (row.ok()) {
      ++solved;
      result.mean_error_at_start += row.error_at_start;
      result.max_error_at_start = std::max(result.max_error_at_start, row.error_at_start);
      result.max_error = std::max(result.max_error, row.error);
      for (int a : commanded) {
        const std::string& unit = model.mechanism().actuators()[static_cast<std::size_t>(a)].unit;
        change[unit] = std::max(change[unit], std::abs(row.commands[a] - row.start[a]));
      }
    } else {
      ++result.failed;
    }
    result.rows.push_back(std::move(row));
  }
  if (solved > 0) result.mean_error_at_start /= solved;
  result.max_change.assign(change.begin(), change.end());
  return result;
}

std::string compensated_csv(const MeasurementModel& model, const CompensateResult& result) {
  const auto actuators = model.mechanism().actuator_names();
  const auto readings = model.reading_names();
  std::ostringstream out;
  out << "line";
  for (const auto& a : actuators) out << ',' << a;
  for (const auto& r : readings) out << ",wanted." << r;
  for (const auto& r : readings) out << ",predicted." << r;
  out << ",error,status,reason\n";
  for (const CompensatedRow& row : result.rows) {
    out << row.line;
    for (Eigen::Index a = 0; a < row.commands.size(); ++a)
      out << ',' << (row.ok() ? fmt(row.commands[a]) : "");
    for (Eigen::Index i = 0; i < row.wanted.size(); ++i) out << ',' << fmt(row.wanted[i]);
    for (Eigen::Index i = 0; i < row.wanted.size(); ++i)
      out << ',' << (row.ok() ? fmt(row.predicted[i]) : "");
    std::string reason = row.reason;
    std::replace(reason.begin(), reason.end(), ',', ';');
    out << ',' << (row.ok() ? fmt(row.error) : "") << ',' << row.status << ',' << reason << '\n';
  }
  return out.str();
}

std::string compensate_text(const MeasurementModel& model, const CompensateResult& result) {
  const auto units = model.reading_units();
  const std::string unit = units.empty() ? "" : units.front();
  char text[400];
  std::ostringstream out;
  std::snprintf(text, sizeof text, "%zu targets (%s): %zu solved, %d failed\n", result.rows.size(),
                result.readings_from.c_str(),
                result.rows.size() - static_cast<std::size_t>(result.failed), result.failed);
  out << text;
  std::snprintf(text, sizeof text,
                "the start commands miss the wanted readings by mean %.4g / max %.4g %s (the "
                "calibrated model's prediction: what compensation corrects)\n",
                result.mean_error_at_start, result.max_error_at_start, unit.c_str());
  out << text;
  std::snprintf(text, sizeof text,
                "the compensated commands reach them to %.3g %s in the model; on the robot, "
                "to the model's own accuracy (kincal validate on held-out data)\n",
                result.max_error, unit.c_str());
  out << text;
  for (const auto& [u, v] : result.max_change) {
    std::snprintf(text, sizeof text, "largest change of a command: %.4g %s\n", v, u.c_str());
    out << text;
  }
  for (const CompensatedRow& row : result.rows)
    if (!row.ok()) out << "line " << row.line << ": " << row.status << ": " << row.reason << '\n';
  return out.str();
}

nlohmann::ordered_json compensate_json(const MeasurementModel& model,
                                       const CompensateResult& result) {
  nlohmann::ordered_json j;
  j["format"] = "kincal-compensate";
  j["version"] = 1;
  j["readings_from"] = result.readings_from;
  j["rows"] = result.rows.size();
  j["failed"] = result.failed;
  j["mean_error_at_start"] = result.mean_error_at_start;
  j["max_error_at_start"] = result.max_error_at_start;
  j["max_error"] = result.max_error;
  nlohmann::ordered_json change = nlohmann::ordered_json::object();
  for (const auto& [u, v] : result.max_change) change[u] = v;
  j["max_change"] = change;
  nlohmann::ordered_json units = nlohmann::ordered_json::object();
  const auto& actuators = model.mechanism().actuators();
  for (const Actuator& a : actuators) units[a.name] = a.unit;
  const auto names = model.reading_names();
  const auto reading_units = model.reading_units();
  for (std::size_t i = 0; i < names.size(); ++i) units[names[i]] = reading_units[i];
  j["units"] = units;
  return j;
}

}  // namespace kincal
