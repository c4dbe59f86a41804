#include "kincal/framework/workflows/kinematics_rows.hpp"

#include <algorithm>
#include <cmath>
#include <limits>
#include <sstream>

#include "kincal/framework/base/angles.hpp"
#include "kincal/framework/kinematics/pose.hpp"
#include "kincal/framework/kinematics/units.hpp"

namespace kincal {

namespace {

// The model's parameter values split as the mechanism takes them.
VectorXd model_values(const MeasurementModel& model) { return model.parameters().nominal_values(); }

KinematicsRow failed(KinematicsRow row, const std::string& status, const std::string& reason) {
  row.status = status;
  row.reason = reason;
  return row;
}

// A reason inside one CSV field: no separators, no line breaks.
std::string csv_text(std::string text) {
  for (char& c : text)
    if (c == ',' || c == '\n' || c == '\r') c = c == ',' ? ';' : ' ';
  return text;
}

nlohmann::ordered_json value_or_null(double v, bool ok) {
  return ok && std::isfinite(v) ? nlohmann::ordered_json(v) : nlohmann::ordered_json();
}

}  // namespace

KinematicsRow forward_row(const MeasurementModel& model, const VectorXd& actuators) {
  KinematicsRow row;
  row.actuators = actuators;
  row.actuators_known = true;
  const VectorXd params = model_values(model);
  const Mechanism& mechanism = model.mechanism();
  const ForwardKinematicsResult fk =
      mechanism.forward_kinematics(params.head(mechanism.num_parameters()), actuators,
                                   mechanism.home_pose(), model.forward_kinematics_options());
  if (!fk.ok()) return failed(row, to_string(fk.status), "forward kinematics " + fk.describe());
  row.readings.resize(model.num_readings());
  model.predict_at_pose(params, fk.pose, row.readings);
  if (!row.readings.allFinite() || !fk.pose.translation.allFinite())
    return failed(row, "overflow",
                  "the pose or readings are not finite numbers (the arithmetic overflows)");
  const Vector3d zyx = euler_zyx(fk.pose.rotation) * (180.0 / kPi);
  row.pose = {fk.pose.translation[0],
              fk.pose.translation[1],
              fk.pose.translation[2],
              zyx[2],
              zyx[1],
              zyx[0]};
  row.pose_known = true;
  return row;
}

KinematicsRow inverse_row(const MeasurementModel& model, const std::array<double, 6>& pose_deg,
                          const VectorXd* near) {
  KinematicsRow row;
  row.pose = pose_deg;
  row.pose_known = true;
  Pose pose;
  pose.translation = Vector3d(pose_deg[0], pose_deg[1], pose_deg[2]);
  pose.rotation =
      rotation_from_euler_zyx(Vector3d(pose_deg[5], pose_deg[4], pose_deg[3]) * kRadiansPerDegree);
  const VectorXd params = model_values(model);
  const Mechanism& mechanism = model.mechanism();
  row.actuators.resize(mechanism.num_actuators());
  if (near && near->size() != mechanism.num_actuators())
    throw std::invalid_argument("the start has " + std::to_string(near->size()) +
                                " values; the model has " +
                                std::to_string(mechanism.num_actuators()) + " actuators");
  const InverseKinematicsResult ik =
      near ? mechanism.inverse_kinematics_near(params.head(mechanism.num_parameters()), pose, *near,
                                               row.actuators)
           : mechanism.inverse_kinematics(params.head(mechanism.num_parameters()), pose,
                                          row.actuators);
  if (!ik.ok()) return failed(row, to_string(ik.status), "inverse kinematics " + ik.describe());
  row.readings.resize(model.num_readings());
  model.predict_at_pose(params, pose, row.readings);
  // Finite input can still overflow (1e308 squared): a status, never inf in the output.
  if (!row.actuators.allFinite() || !row.readings.allFinite())
    return failed(row, "overflow",
                  "the actuator values or readings are not finite numbers (the arithmetic "
                  "overflows)");
  row.actuators_known = true;
  return row;
}

std::vector<KinematicsRow> inverse_solutions(const MeasurementModel& model,
                                             const std::array<double, 6>& pose,
                                             const VectorXd* near, int starts) {
  const Mechanism& mechanism = model.mechanism();
  const int n = mechanism.num_actuators();
  VectorXd home(n);
  const VectorXd params = model_values(model);
  if (!mechanism.home_actuators(params.head(mechanism.num_parameters()), home).ok())
    home = VectorXd::Zero(n);
  const VectorXd centre = near ? *near : home;
  // The start of attempt k: the centre first, then a deterministic spread (a Halton-like
  // sequence per joint) over the joints' ranges; inputs nobody commands stay at the centre.
  const auto start = [&](int k) {
    VectorXd s = centre;
    if (k == 0) return s;
    for (int i = 0; i < n; ++i) {
      const Actuator& a = mechanism.actuators()[static_cast<std::size_t>(i)];
      if (!a.commanded) continue;
      const double u = std::fmod(0.5 + k * (0.6180339887498949 + 0.1 * std::sqrt(2.0 + i)), 1.0);
      const double half = a.unit == kRadian ? kPi : 3 * a.default_range;
      s[i] = centre[i] + (2 * u - 1) * half;
    }
    return s;
  };
  const auto same = [&](const VectorXd& a, const VectorXd& b) {
    for (int i = 0; i < n; ++i) {
      double d = a[i] - b[i];
      if (mechanism.actuators()[static_cast<std::size_t>(i)].unit == kRadian) d = wrap_angle(d);
      if (std::abs(d) > 1e-6) return false;
    }
    return true;
  };
  std::vector<KinematicsRow> found;
  for (int k = 0; k <= starts; ++k) {
    const VectorXd s = start(k);
    KinematicsRow row = inverse_row(model, pose, &s);
    if (!row.ok()) continue;
    // A revolute joint's angle within half a turn of the centre: the same configuration.
    for (int i = 0; i < n; ++i)
      if (mechanism.actuators()[static_cast<std::size_t>(i)].unit == kRadian)
        row.actuators[i] = centre[i] + wrap_angle(row.actuators[i] - centre[i]);
    bool known = false;
    for (const KinematicsRow& f : found) known = known || same(f.actuators, row.actuators);
    if (!known) found.push_back(std::move(row));
  }
  const auto distance = [&](const KinematicsRow& r) { return (r.actuators - centre).norm(); };
  std::stable_sort(found.begin(), found.end(), [&](const KinematicsRow& a, const KinematicsRow& b) {
    return distance(a) < distance(b);
  });
  return found;
}

std::string rows_csv(const MeasurementModel& model, const std::vector<KinematicsRow>& rows) {
  std::ostringstream out;
  out.precision(std::numeric_limits<double>::max_digits10);
  out << "line";
  for (const auto& name : model.mechanism().actuator_names()) out << ',' << name;
  for (const auto& name : kPoseColumns) out << ',' << name;
  for (const auto& name : model.reading_names()) out << ',' << name;
  out << ",status,reason\n";
  for (const auto& row : rows) {
    out << row.line;
    for (Eigen::Index i = 0; i < model.mechanism().num_actuators(); ++i) {
      out << ',';
      if (row.actuators_known) out << row.actuators[i];
    }
    for (double v : row.pose) {
      out << ',';
      if (row.pose_known) out << v;
    }
    for (Eigen::Index k = 0; k < model.num_readings(); ++k) {
      out << ',';
      if (row.ok()) out << row.readings[k];
    }
    out << ',' << row.status << ',' << csv_text(row.reason) << '\n';
  }
  return out.str();
}

nlohmann::ordered_json row_json(const MeasurementModel& model, const KinematicsRow& row) {
  nlohmann::ordered_json j;
  if (row.line > 0) j["line"] = row.line;
  j["status"] = row.status;
  if (!row.ok()) j["reason"] = row.reason;
  nlohmann::ordered_json actuators, pose, readings;
  const auto names = model.mechanism().actuator_names();
  for (std::size_t i = 0; i < names.size(); ++i)
    actuators[names[i]] =
        value_or_null(row.actuators_known ? row.actuators[i] : 0, row.actuators_known);
  for (std::size_t i = 0; i < kPoseColumns.size(); ++i)
    pose[kPoseColumns[i]] = value_or_null(row.pose[i], row.pose_known);
  const auto reading_names = model.reading_names();
  for (std::size_t k = 0; k < reading_names.size(); ++k)
    readings[reading_names[k]] = value_or_null(row.ok() ? row.readings[k] : 0, row.ok());
  j["actuators"] = actuators;
  j["pose"] = pose;
  j["readings"] = readings;
  return j;
}

nlohmann::ordered_json rows_json(const std::string& format, const std::string& model_file,
                                 const std::string& input_file, const MeasurementModel& model,
                                 const std::vector<KinematicsRow>& rows) {
  nlohmann::ordered_json units;
  for (const auto& a : model.mechanism().actuators()) units[a.name] = a.unit;
  const auto names = model.reading_names();
  const auto reading_units = model.reading_units();
  for (std::size_t k = 0; k < names.size(); ++k) units[names[k]] = reading_units[k];
  nlohmann::ordered_json list = nlohmann::ordered_json::array();
  int failures = 0;
  for (const auto& row : rows) {
    list.push_back(row_json(model, row));
    failures += !row.ok();
  }
  return {{"format", format}, {"version", 1}, {"model", model_file}, {"input", input_file},
          {"units", units},   {"rows", list}, {"failed", failures}};
}

}  // namespace kincal
