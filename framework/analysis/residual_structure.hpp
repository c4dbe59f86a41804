#pragma once
// Whether a fit's residuals are noise or a model error, whatever noise the model states.
//
// A chi-square against the stated noise cannot tell the two apart: real set-ups scatter more
// than their sensor's datasheet (robot repeatability, temperature), so it fires on good fits,
// and a model without a stated noise has nothing to compare with. What does tell them apart
// is shape. Noise is independent from one configuration to the next; a model error (a frame
// frozen at a wrong value, readings in other units, a wrong fixed parameter) is a smooth
// function of the configuration. Three measures, each from the fit alone:
//
//   neighbour_fraction  phi = 1 - s_nn^2 / s^2: s^2 the mean square of the whitened residuals,
//                       s_nn^2 half the mean square difference between each configuration's
//                       residuals and those of its nearest neighbour in actuator space (each
//                       actuator scaled by its spread in the data). Independent noise gives
//                       phi ~ 0 (within neighbour_z standard errors); residuals shared by
//                       neighbours give phi -> 1. Repeats of a configuration are its nearest
//                       neighbours: they measure the noise directly.
//   fixed_fraction      the share of the residual sum of squares that the fixed parameters'
//                       Jacobian columns explain beyond the free ones (a frozen frame's
//                       signature), with the F-test's p-value and the one fixed parameter
//                       that explains most on its own. Pure noise: about p / (m - n).
//   unexplained_spread  per reading unit, the residuals' robust RMS (1.4826 x the median
//                       |residual|) over the readings' own RMS
//                       spread about their mean: how much of what the sensor saw the model
//                       does not explain (rows shuffled between configurations: most of it).
//
// Large data are sampled (at most kStructureSampleConfigurations evenly spaced
// configurations), so the measures cost milliseconds on 10^6 rows.

#include <map>
#include <string>

#include "kincal/framework/calibration/calibration_problem.hpp"

namespace kincal {

constexpr int kStructureSampleConfigurations = 4000;

struct ResidualStructure {
  bool tested = false;
  std::string not_tested;  ///< why not (too few configurations, evaluation failed)

  int pairs = 0;                         ///< neighbour pairs compared
  double neighbour_fraction = NAN;       ///< phi
  double neighbour_z = NAN;              ///< phi / its standard error under independent noise
  double mean_neighbour_distance = NAN;  ///< in units of each actuator's spread

  int fixed_directions = 0;     ///< rank the fixed parameters add to the free ones
  double fixed_fraction = NAN;  ///< share of the residual sum of squares they explain
  double fixed_p = NAN;         ///< P(that share or more | independent noise), an F-test
  /// The residual degrees of freedom the F-test estimates the noise from: readings less the
  /// free and the fixed directions. Few of them (kMinShapeDegreesOfFreedom) and the test
  /// cannot tell a model error from noise.
  int fixed_test_dof = 0;
  std::string dominant_fixed;  ///< the fixed parameter explaining most on its own
  double dominant_fixed_fraction = NAN;

  /// Per reading unit: residual RMS / RMS spread of the readings about their mean.
  std::map<std::string, double> unexplained_spread;
  std::map<std::string, double> reading_spread;  ///< that spread, in the unit

  /// The verdicts' thresholds (calibration_verdict.cpp).
  bool neighbour_structured() const;
  bool fixed_structured() const;
};

/// The measures at the free parameters `x` of `problem` (whitened residuals, as the problem
/// weighs them: divided by reading_std when the model states it).
ResidualStructure analyze_residual_structure(const CalibrationProblem& problem, const VectorXd& x);

/// Share of the residuals' variance above which neighbours are said to share them, and the
/// number of standard errors it must also reach.
constexpr double kNeighbourStructured = 0.5;
constexpr double kNeighbourZ = 5;
/// Share of the residual sum of squares the fixed parameters must explain, and how unlikely
/// that must be under noise, for a frozen parameter to be named.
constexpr double kFixedStructured = 0.25;
constexpr double kFixedProbability = 1e-6;
/// A robust residual RMS above this share of the readings' spread: the model does not explain what
/// the sensor saw. Readings that do not belong to their rows leave about the whole spread (117 %
/// on the UR5's readings shuffled between rows, 71 % for Euler angles read as a rotation
/// vector); a good calibration leaves its sensor's noise: 1e-4 to 1e-3 for a tracker, but 1 %
/// for a camera with 1 px of noise on a target that moves 100 px, which 1 %, the threshold
/// before cameras, called a model that explains nothing.
constexpr double kUnexplainedSpread = 0.1;
/// Below this many residual degrees of freedom beyond the free and fixed directions, the
/// fixed-parameter F-test has too little power to clear a fit (a 3 mm error of a fixed
/// parameter in 40 gauge readings, 24 free and 13 fixed directions: P 0.09).
constexpr int kMinShapeDegreesOfFreedom = 10;

}  // namespace kincal
