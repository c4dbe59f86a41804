#pragma once
// Whether a fit's residuals are what the noise predicts (calibrate's report, simulate): the
// solver's "converged" says only that it stopped, not that it stopped at the global minimum.

#include <cmath>
#include <string>

namespace kincal {

/// A fit whose residuals are this improbable under the stated noise (P(chi^2 >= observed))
/// is reported as probably a local minimum or a model error.
constexpr double kFitCheckProbability = 1e-4;

/// What the reports say of such a fit.
inline constexpr const char* kFitTooLarge =
    "the residuals are far above the stated noise: probably a local minimum or a model error "
    "(try --starts, check the fixed parameters, outliers and reading_std)";

/// What calibrate's report says of a fit above its stated noise: by itself no model error
/// (the residuals' shape tells: framework/analysis/residual_structure.hpp).
inline constexpr const char* kFitAboveStatedNoise =
    "the residuals are above the stated noise; whether that is the set-up's noise or a model "
    "error is what the residuals' shape tells (residual_structure, and the verdict)";

/// What they say of a fit that passes: the check has a blind side.
inline constexpr const char* kFitConsistent =
    "consistent with the noise (a local minimum whose residuals are as small as the noise "
    "passes too: --starts compares minima)";

/// Why a model without reading_std is not checked: the noise would have to be estimated from
/// these very residuals, against which any fit is consistent.
inline constexpr const char* kFitNoNoise =
    "the model states no reading noise (reading_std or --noise-std): sigma_hat is estimated "
    "from these residuals, so they cannot be compared with the noise, and a local minimum or "
    "a model error can only show as a sigma_hat larger than the sensor's accuracy";

/// The residuals of the fit against the noise (the model's reading_std, or a simulation's): at
/// the global minimum of a right model with Gaussian noise, sum (r_i / std_i)^2 follows
/// chi-square on m - n degrees of freedom (to first order). A value far above it means the
/// solver stopped in a local minimum or the model misses something (a wrong fixed parameter,
/// outliers, a too optimistic std). Uniform noise, as simulated, has lighter tails, so the
/// probability is then conservative. The converse does not hold: a local minimum whose
/// residuals are no larger than the noise's passes (docs/benchmarks.md, "Local minima").
struct FitCheck {
  bool tested = false;
  std::string not_tested;  ///< why not, when !tested
  double chi_square = NAN;
  int degrees_of_freedom = 0;
  double p_larger = NAN;  ///< P(chi^2 >= observed)
  bool too_large() const { return tested && p_larger < kFitCheckProbability; }
};

}  // namespace kincal
