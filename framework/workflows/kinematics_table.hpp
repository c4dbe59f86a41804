#pragma once
// Forward and inverse kinematics as workflows (kincal fk and ik; kincal.fk and kincal.ik in
// Python): one configuration or pose, or a table of them read from a CSV file, and the
// documents and text both faces write. The per-row kernels are kinematics_rows.hpp's.
//
//   KinematicsTableRequest request;
//   request.inverse = true;                // ik: poses in, actuator values out
//   request.data_file = "targets.csv";     // x_mm, y_mm, z_mm, rx_deg, ry_deg, rz_deg
//   const KinematicsTable table = kinematics_table(*model, request);
//   write(rows_csv(*model, table.rows));   // a row per line, failures as statuses

#include <nlohmann/json.hpp>
#include <string>
#include <vector>

#include "kincal/framework/calibration/measurement_file.hpp"
#include "kincal/framework/workflows/kinematics_rows.hpp"

namespace kincal {

struct KinematicsTableRequest {
  bool inverse = false;   ///< ik (a pose per row) rather than fk (actuator values per row)
  std::string data_file;  ///< the CSV: a measurement file's actuator columns, or kPoseColumns
  /// ik: start each row from the configuration in its own actuator columns (unit suffixes
  /// such as _deg allowed), the solution nearest it.
  bool seeds = false;
  /// ik without seeds: the solution nearest these actuator values (empty: from home).
  VectorXd near;
  CsvLimits limits;
  /// How the face spells its options in the notes (option_name.hpp): "--" for the program,
  /// "" for Python.
  std::string option_prefix = "--";
};

struct KinematicsTable {
  std::vector<KinematicsRow> rows;  ///< one per data line, each with its line and status
  std::vector<std::string> notes;   ///< about the file: columns not read, units converted
  int failures = 0;                 ///< rows whose status is not "ok"
};

/// "q1,q2,...": one value per actuator in its own unit, or each followed by its unit (90deg,
/// 1.2rad, 350mm, 0.35m), converted to that unit. A revolute joint's value beyond one turn
/// without a unit is refused as degrees, as in a measurement file. Throws
/// std::invalid_argument "<label> '<text>': ..." naming the field.
std::vector<double> parse_actuator_values(const std::string& text, const MeasurementModel& model,
                                          const std::string& label);

/// "x,y,z,rx,ry,rz" (mm and degrees) as six numbers; throws as parse_actuator_values.
std::array<double, 6> parse_pose_values(const std::string& text, const std::string& label);

/// Forward kinematics of one configuration given as parse_actuator_values's text. Throws
/// std::invalid_argument "<label> '<text>': ..." when it cannot be computed (unreachable,
/// singular, readings that overflow).
KinematicsRow forward_at(const MeasurementModel& model, const std::string& text,
                         const std::string& label);
/// Inverse kinematics at one pose given as parse_pose_values's text, from home or the solution
/// nearest `near`; throws as forward_at.
KinematicsRow inverse_at(const MeasurementModel& model, const std::string& text,
                         const std::string& label, const VectorXd* near);
/// inverse_solutions at one pose given as text, nearest `near` (or home) first; throws when
/// none is found.
std::vector<KinematicsRow> inverse_solutions_at(const MeasurementModel& model,
                                                const std::string& text, const std::string& label,
                                                const VectorXd* near);

/// Reads the request's file (columns as measurement files: a header, other columns ignored
/// with a note, the model's reading columns silently) and computes a row per line.
/// Throws std::invalid_argument naming the file (unreadable, malformed, values in the wrong
/// unit); a row that cannot be computed is a status, not an error.
KinematicsTable kinematics_table(const MeasurementModel& model,
                                 const KinematicsTableRequest& request);

/// The JSON document of one result (fk --actuators, ik --pose): {"format": "kincal-fk" or
/// "kincal-ik", "version": 1, "model": model_file, ...row_json}.
nlohmann::ordered_json kinematics_row_document(bool inverse, const std::string& model_file,
                                               const MeasurementModel& model,
                                               const KinematicsRow& row);
/// The document of ik --all: {"format": "kincal-ik", "version", "model", "solutions": [...]}.
nlohmann::ordered_json kinematics_solutions_document(const std::string& model_file,
                                                     const MeasurementModel& model,
                                                     const std::vector<KinematicsRow>& solutions);

/// What fk prints for one configuration: position_mm, rotation_deg and each reading.
std::string forward_row_text(const MeasurementModel& model, const KinematicsRow& row);
/// What ik prints for one pose: each actuator value (nanoradians or micrometres) and reading.
std::string inverse_row_text(const MeasurementModel& model, const KinematicsRow& row);
/// The same for each solution of ik --all, headed "solution k of n", the first "(nearest
/// --near)" when `near_given`, else "(nearest home)".
std::string inverse_solutions_text(const MeasurementModel& model,
                                   const std::vector<KinematicsRow>& solutions, bool near_given);
/// The line after one ik result: "(actuator units: name unit, ...)".
std::string actuator_units_line(const MeasurementModel& model);

}  // namespace kincal
