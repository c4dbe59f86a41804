#pragma once
// An estimate on the branch of the model nearest its nominal values, and what is far from it.
//
// Least squares sees only the predictions, so an estimate is one of a set of parameter vectors
// that predict the same: every angle up to whole turns, and, for some mechanisms, discrete
// symmetries (an arm's joint zero turned by pi with the next links turned back: the same poses,
// links drawn backwards; Mechanism::nearer_equivalent). A solver that wanders far from the
// start can end anywhere in that set. Exported as it is, such an estimate is a different robot
// description with the same fit. So the estimate is mapped to the member nearest the nominal
// values, but only when the map is exact: every prediction at the data's configurations must
// stay the same (to 1e-9 of the readings' scale, and the fixed parameters may not move);
// otherwise it stays as solved. What is still far from nominal after the map (an angle on
// another branch, a correction far beyond the model's tolerance) is reported by
// calibration_verdict.hpp.

#include <string>
#include <vector>

#include "kincal/framework/calibration/calibration_problem.hpp"

namespace kincal {

struct NominalBranch {
  VectorXd x;  ///< the free parameters, mapped (equal to the input when nothing was)
  /// What was mapped, in words (empty when nothing was): angles moved by whole turns, and the
  /// mechanism's symmetries.
  std::vector<std::string> mapped;
  /// The largest change of a prediction the map made, in the readings' units (checked against
  /// kEquivalentPredictionTolerance).
  double prediction_change = 0;
  /// A map the mechanism proposed whose predictions differ: kept out, said here.
  std::string rejected;
};

/// Relative to the largest |reading|: a mapped estimate may change no prediction by more.
constexpr double kEquivalentPredictionTolerance = 1e-9;

/// Each free parameter's tolerance, the scale of "far from nominal": the model's param_error
/// (a half-width), else 3 x prior_std, else 5 mm or 0.01 rad (the assumption the nominal
/// pose-accuracy prediction makes); `assumed[i]` tells the last case.
VectorXd parameter_tolerances(const MeasurementModel& model, std::vector<bool>* assumed = nullptr);

/// A correction beyond this many times its tolerance is "far beyond" it: the fit absorbed
/// something that is not the geometry (calibration_verdict.hpp).
constexpr double kFarBeyondTolerance = 10;

/// The estimate `x` of `problem` on the branch nearest the problem's starting values.
NominalBranch map_to_nominal_branch(const CalibrationProblem& problem, const VectorXd& x);

}  // namespace kincal
