#pragma once
// Checks of measurement data against a model that catch set-up mistakes before they turn into
// a wrong calibration (docs/calibrating-a-machine.md, "Setting up a real machine"):
//   - home_pose: forward kinematics starts from the model's home pose and converges to the
//     assembly nearest to it. A wrong home_pose gives a different, valid pose; when the
//     data's poses all lie far from home_pose, it is probably wrong.
//   - encoder strokes: actuator values given as strokes (zero at a reference mark) instead of
//     leg lengths fail forward kinematics at most rows; the leg offsets are the fix.
//   - units: values of a column that look like the wrong unit (joint angles in degrees where
//     the model takes radians, lengths in metres where it takes millimetres), for any
//     mechanism; a column named with a unit suffix (joint1_deg) says its unit and is trusted.
// Each check returns one plain sentence, empty when nothing looks wrong.

#include <string>

#include "kincal/framework/calibration/calibration_problem.hpp"
#include "kincal/framework/calibration/measurement_file.hpp"

namespace kincal {

/// Where the poses of the data (forward kinematics of each row at `params`) lie relative to
/// the model's home_pose.
struct HomePoseCheck {
  int poses = 0;                   ///< rows whose forward kinematics succeeded
  double nearest_position_mm = 0;  ///< distance of the closest pose to home_pose
  double nearest_angle_rad = 0;    ///< rotation angle of the closest pose from home_pose
  double extent_mm = 0;            ///< largest distance of a pose from the poses' centre
  double extent_angle_rad = 0;     ///< largest rotation of a pose from the central one
  /// Far: even the closest pose is farther from home than the data spreads, and farther
  /// than kHomeFarMm / kHomeFarRad (so that a compact data set near home is never "far").
  bool far = false;
  std::string warning;  ///< the sentence for the user when far, else empty
};
constexpr double kHomeFarMm = 10.0;
/// Readings whose spread differs from the predicted spread by more than this factor.
constexpr double kSpreadMismatch = 20;
constexpr double kHomeFarRad = 0.2;

/// Only for mechanisms whose forward kinematics has several assemblies
/// (Mechanism::forward_kinematics_has_assemblies); for a serial arm it is never far.
HomePoseCheck check_poses_near_home(const MeasurementModel& model, const VectorXd& params,
                                    const Measurements& data);

/// A hint when rows fail forward kinematics (`failed_rows` of data.size()) and the actuator
/// values look like encoder strokes: at least half the rows failed, and the median |value| of
/// most length actuators is below a quarter of that actuator's value at home. Empty
/// otherwise.
std::string encoder_stroke_hint(const MeasurementModel& model, const VectorXd& params,
                                const Measurements& data, int failed_rows);

/// Values beyond one turn (|value| > 2 pi) in an angle column (a revolute joint, an angle
/// reading) read without a unit suffix are degrees. Length actuators whose values are about
/// a thousandth of their length at home (median ratio within [1/3000, 1/300]) are metres.
/// Length readings (mm) that the model at `params` predicts ten times better when multiplied
/// by 1000 are metres (checked only when `table` holds the model's readings and forward
/// kinematics reaches the rows; from 20000 rows on, on evenly spaced rows, 10000 to 20000
/// of them). Returns one sentence saying what was seen and how to fix it
/// (name the columns <name>_deg / <name>_m, or convert), or "" when nothing looks wrong.
/// Columns read with a unit suffix are not checked: the suffix states the unit. Then, for every
/// sensor's length readings whatever their columns, the spread of the readings against the
/// spread the model predicts at the same configurations (a point's RMS distance from its
/// centre, which no frame changes): beyond kSpreadMismatch times apart, one way or the
/// other, the units are wrong (metres named) or the data are not this machine's.
std::string check_data_units(const MeasurementModel& model, const VectorXd& params,
                             const MeasurementTable& table);

/// Rows measured at the same configuration. A row whose actuators and readings equal an
/// earlier row's bit for bit is a copy, not a second measurement (no two real readings agree
/// to the last digit), and counts once; rows at the same actuator values with different
/// readings are repeats, whose scatter is the noise.
struct Repeats {
  std::vector<int> duplicates;      ///< 0-based rows that copy an earlier row, ascending
  std::vector<int> duplicate_of;    ///< the earlier row each copies
  int repeated_configurations = 0;  ///< configurations with two or more distinct rows
  int repeat_rows = 0;              ///< the distinct rows at those configurations
};
Repeats find_repeats(const Measurements& data);

}  // namespace kincal
