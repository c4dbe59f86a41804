#pragma once
// The compensate workflow: corrected targets for the controller. Given what the sensor should
// read (a point tracker's target where it is wanted, in the measurement frame; a pose
// tracker's frame) and a calibrated model, the actuator commands that make the model read
// exactly that: geometry, joint deflection under gravity and payload (models/
// joint_compliance.hpp) included, since the model's forward kinematics holds them. A
// controller that only knows its nominal kinematics sent these commands puts the tool where
// it was wanted, to the calibrated model's accuracy. What `kincal compensate` does between
// reading its files and writing its outputs, as one library call (Python: kincal.compensate).
//
// Each row is solved by damped Gauss-Newton on the readings' error over the commanded
// actuators (Actuator::commanded; inputs such as a payload's mass stay as given), from a
// start: the row's own commands when it has them (the commands a program already holds: the
// solution nearest them, the branch they are on), else `near`, else the model's home. With
// more commanded actuators than readings (6 joints, a 3-D point) each step is the smallest
// that reduces the error, so the commands stay near the start. A row that cannot be reached
// is a status with a reason, never a command.
//
//   kincal::CompensateRequest request;
//   request.model = calibrated;                       // its nominal values
//   request.targets = kincal::read_compensate_targets("targets.csv", *calibrated, nominal);
//   const kincal::CompensateResult r = kincal::compensate(request);
//   // r.rows[i].commands; compensated_csv(*calibrated, r)

#include <memory>
#include <nlohmann/json.hpp>
#include <string>
#include <vector>

#include "kincal/framework/kinematics/measurement_model.hpp"

namespace kincal {

/// The wanted readings of the rows, and the commands each starts from.
struct CompensateTargets {
  MatrixXd readings;  ///< rows x num_readings: what the sensors should read
  /// rows x num_actuators: each row's start (its commands, or `near`/home filled in), and the
  /// inputs that are not commanded (the payload's mass).
  MatrixXd starts;
  std::vector<int> lines;  ///< the file line of each row; empty for rows given in memory
  /// Where the wanted readings came from, in words: "the file's reading columns", "the
  /// nominal model 'nominal.json' at the file's commands".
  std::string readings_from;
  bool starts_from_file = false;  ///< the file gave each row's commands
};

/// The targets in `path`: the model's reading columns (the wanted readings, units as in
/// measurement files), and the actuator columns when present (each row's start). With a
/// `nominal` model, the file needs only the commanded actuator columns: the wanted readings
/// are what the nominal model predicts there (the commands a program computed with the
/// controller's nominal kinematics, corrected to reach what it meant). `near` (empty: the
/// model's home) starts rows without commands; `inputs` gives non-commanded actuators (the
/// payload) that the file lacks (empty: their home values). Throws std::invalid_argument
/// "<path>:<line>: ..." for a missing column, some commanded actuator columns but not all,
/// an empty or unreadable value, a nominal model whose actuators or readings differ.
CompensateTargets read_compensate_targets(
    const std::string& path, const MeasurementModel& model, const MeasurementModel* nominal,
    const VectorXd& near, const std::vector<std::pair<std::string, double>>& inputs);

struct CompensateRequest {
  std::shared_ptr<const MeasurementModel> model;  ///< its nominal values are used
  CompensateTargets targets;
  /// Solved when every reading is within this of its wanted value (in the reading's unit).
  double tolerance = 1e-9;
  int max_iterations = 200;
};

struct CompensatedRow {
  int line = 0;
  VectorXd commands;   ///< the compensated actuator values (inputs as given)
  VectorXd start;      ///< the commands it started from
  VectorXd wanted;     ///< the wanted readings
  VectorXd predicted;  ///< the model's readings at `commands`
  /// The model's readings at `start`: what the uncompensated commands give.
  VectorXd predicted_at_start;
  double error = 0;           ///< |predicted - wanted| (readings' norm, their unit)
  double error_at_start = 0;  ///< |predicted_at_start - wanted|
  int iterations = 0;
  std::string status = "ok";  ///< "ok", "not_converged", "unreachable"
  std::string reason;
  bool ok() const { return status == "ok"; }
};

struct CompensateResult {
  std::vector<CompensatedRow> rows;
  int failed = 0;
  /// Over the rows solved: the error the start commands leave (mean, max) and the largest
  /// left after compensation, in the readings' unit.
  double mean_error_at_start = 0, max_error_at_start = 0, max_error = 0;
  /// The largest change of a commanded actuator, per unit ("rad", "mm").
  std::vector<std::pair<std::string, double>> max_change;
  std::string readings_from;
};

CompensateResult compensate(const CompensateRequest& request);

/// CSV: line, the actuator columns (compensated), the wanted readings (wanted.<reading>), the
/// predicted readings, error, status, reason; 17 significant digits, empty values on failure.
std::string compensated_csv(const MeasurementModel& model, const CompensateResult& result);

/// The summary as printed by `kincal compensate`.
std::string compensate_text(const MeasurementModel& model, const CompensateResult& result);

/// {"format": "kincal-compensate", "version": 1, "readings_from", "rows", "failed",
///  "mean_error_at_start", "max_error_at_start", "max_error", "max_change": {unit: value},
///  "units": {...}}
nlohmann::ordered_json compensate_json(const MeasurementModel& model,
                                       const CompensateResult& result);

}  // namespace kincal
