#pragma once
// Forward and inverse kinematics of a model, one pose at a time or a table of them (kincal fk
// and ik, cli/command_fk.cpp and command_ik.cpp; Model.forward_kinematics and
// inverse_kinematics in Python), and their CSV and JSON forms.
//
// The angle rule (docs/calibrating-a-machine.md, "Units and angles"): every option, column
// and JSON field that holds an angle says its unit in its name. Poses a person writes or
// reads (fk, ik, the model file's home_pose) are x, y, z in mm and Z-Y-X Euler angles in
// degrees: columns x_mm, y_mm, z_mm, rx_deg, ry_deg, rz_deg. Computed results (errors,
// parameters, standard deviations) are in radians, named *_rad or with a "unit" field.

#include <array>
#include <nlohmann/json.hpp>
#include <string>
#include <vector>

#include "kincal/framework/kinematics/measurement_model.hpp"

namespace kincal {

/// The pose columns of a poses file (ik --data) and of fk's table output, in order.
inline const std::vector<std::string> kPoseColumns = {"x_mm",   "y_mm",   "z_mm",
                                                      "rx_deg", "ry_deg", "rz_deg"};

/// One configuration: actuator values, pose and readings, or why they could not be computed.
struct KinematicsRow {
  int line = 0;                  ///< line in the input file; 0 for a command-line value
  VectorXd actuators;            ///< given (fk) or computed (ik)
  std::array<double, 6> pose{};  ///< x, y, z (mm), rx, ry, rz (deg): computed (fk) or given (ik)
  VectorXd readings;             ///< the sensors' readings at the pose
  bool actuators_known = false;  ///< given, or computed successfully
  bool pose_known = false;       ///< given, or computed successfully
  std::string status = "ok";     ///< "ok", or the failure ("singular", "unreachable", ...)
  std::string reason;            ///< one sentence when not ok
  bool ok() const { return status == "ok"; }
};

/// Forward kinematics from the model's home pose at the model's values.
KinematicsRow forward_row(const MeasurementModel& model, const VectorXd& actuators);
/// Inverse kinematics at `pose` (x, y, z mm, rx, ry, rz deg), from the model's home, or from
/// `near` (the actuator values the solution should be nearest: a serial arm's branch).
KinematicsRow inverse_row(const MeasurementModel& model, const std::array<double, 6>& pose,
                          const VectorXd* near = nullptr);

/// The distinct solutions inverse kinematics finds at `pose` from `near` (or home) and from
/// `starts` more starting points spread over each joint's range (revolute: ±π around home;
/// prismatic: 3 default ranges), nearest `near` (or home) first. Solutions that differ only by
/// whole turns of revolute joints are one, their angles given within half a turn of `near`
/// (or home). Joint limits are not checked. Empty when none is found.
std::vector<KinematicsRow> inverse_solutions(const MeasurementModel& model,
                                             const std::array<double, 6>& pose,
                                             const VectorXd* near = nullptr, int starts = 200);

/// CSV: line, the actuator columns, the pose columns, the reading columns, status, reason.
/// Values of a failed row are empty. 17 significant digits.
std::string rows_csv(const MeasurementModel& model, const std::vector<KinematicsRow>& rows);

/// {"line"?, "status", "reason"?, "actuators": {name: value}, "pose": {x_mm: ...},
///  "readings": {name: value}}; the values are null when the row failed.
nlohmann::ordered_json row_json(const MeasurementModel& model, const KinematicsRow& row);
/// {"format": format, "model", "input", "units": {actuator or reading: unit}, "rows": [...],
///  "failed": count}.
nlohmann::ordered_json rows_json(const std::string& format, const std::string& model_file,
                                 const std::string& input_file, const MeasurementModel& model,
                                 const std::vector<KinematicsRow>& rows);

}  // namespace kincal
