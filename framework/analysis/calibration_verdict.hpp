#pragma once
// The verdict on a calibration: whether to load it, as data. Each finding says what was seen,
// how serious it is and what to do; the text, JSON and HTML reports render the same list, and
// `calibrate` exits with kDoNotLoadExitCode when one finding says not to load the result.
//
// What makes a calibration one not to load, whatever the solver said:
//   - the solver reached no solution;
//   - an angle of the mechanism's geometry on another branch than its nominal (a joint zero
//     near nominal + pi) that no exact symmetry maps back (equivalent_solutions.hpp);
//   - corrections far beyond the model's tolerances (kFarBeyondTolerance of them), outside the
//     frames that place the mechanism and the measured point (those have no tolerance unless
//     the model states one): the fit absorbed something that is not the geometry (a mirrored
//     axis, swapped columns, other units);
//   - residuals that leave most of the readings' spread unexplained (residual_structure.hpp);
//   - a fit worse than its own registration-only baseline, on the calibration data or held
//     out: a local minimum, or over-fitting;
//   - a position error no better than before, or a predicted one that does not beat nominal.
// Structured residuals (a frozen frame, a model error) are a warning: check before loading.
// Residuals merely larger than the stated noise, without structure, are a note with the noise
// estimated: real set-ups scatter more than their sensor's datasheet.

#include <string>
#include <vector>

#include "kincal/framework/analysis/calibration_report.hpp"

namespace kincal {

struct Finding {
  enum class Level { kGood, kNote, kWarning, kDoNotLoad };
  std::string id;  ///< what it is about: solver, branch, tolerance, fit, baseline, accuracy, ...
  Level level = Level::kNote;
  std::string text;    ///< what was found
  std::string advice;  ///< what to do; empty when nothing
};

const char* to_string(Finding::Level level);

struct CalibrationVerdict {
  std::vector<Finding> findings;
  /// The most serious level among the findings (kGood when there are none).
  Finding::Level worst() const;
  /// "load", "check" (a warning) or "do_not_load".
  std::string overall() const;
};

/// A calibrated fit whose RMS error exceeds its registration-only baseline's by more than
/// this factor is worse than the baseline (the full fit contains the baseline's parameters,
/// so at its minimum it can only be as good or better).
constexpr double kWorseThanBaseline = 1.05;
/// sigma_hat (in multiples of the stated noise) above which unstructured residuals are a
/// warning rather than a note, and below which they are as stated.
constexpr double kNoiseFarAboveStated = 10;
constexpr double kNoiseAsStated = 1.5;

/// `calibrate`'s exit code when it wrote its outputs but its verdict is do_not_load.
constexpr int kDoNotLoadExitCode = 3;

/// The findings on a filled report (baselines and cross-validation included).
CalibrationVerdict judge_calibration(const CalibrationReport& report);

nlohmann::ordered_json to_json(const CalibrationVerdict& verdict);
/// "verdict: ..." then one line per finding that is not good.
std::string to_text(const CalibrationVerdict& verdict);

}  // namespace kincal
