#pragma once
// The observability workflow: how well a model's free parameters are determined by a set of
// configurations, before any solving (the identification Jacobian at the model's values, with
// the prior the model states). What `kincal observability` does between reading its files and
// writing its outputs, as one library call.
//
//   kincal::ObservabilityRequest request;
//   request.model = model;
//   request.data = kincal::random_configurations(*model, 40, /*seed=*/1, {});
//   const kincal::ObservabilityResult r = kincal::observe(request);
//   std::cout << kincal::observability_text(r);   // rank, condition number, per parameter

#include <memory>
#include <string>
#include <vector>

#include <nlohmann/json.hpp>

#include "kincal/framework/analysis/identifiability.hpp"
#include "kincal/framework/calibration/calibration_problem.hpp"
#include "kincal/framework/kinematics/units.hpp"

namespace kincal {

struct ObservabilityRequest {
  /// The model at its nominal values, its free mask, prior_std and reading_std. Not modified.
  std::shared_ptr<const MeasurementModel> model;
  /// The configurations analysed (their readings are not used: only where they were taken).
  Measurements data;
  IdentifiabilityOptions identifiability;
  /// The free set was given explicitly (--free/--fix): calibrate would not choose one, so the
  /// result does not say which parameters it would keep.
  bool explicit_mask = false;
  /// Names of the inputs, in the report only; may be empty.
  std::string model_file;
  std::string source;  ///< the data's file, or "N random configurations"
};

struct ObservabilityResult {
  int configurations = 0;
  Identifiability identifiability;
  /// The model states a prior on a free parameter: `identifiability` includes it, and its
  /// data_share says how much of each parameter the data determine.
  bool with_prior = false;
  int num_free = 0;
  /// Where calibrate would choose the identifiable set itself (an arm imported from a URDF,
  /// no explicit mask, no prior) and the data do not determine every free parameter: the
  /// parameters it would keep, and what each of the others duplicates, in words.
  std::vector<std::string> calibrate_keeps, null_directions;
  std::string model_file, source;
};

/// Runs the analysis. Throws std::invalid_argument when the model has no free parameter, a
/// prior without reading_std, or the Jacobian cannot be evaluated at the model's values.
ObservabilityResult observe(const ObservabilityRequest& request);

/// `count` configurations drawn around the model's home actuator values, U[-r, r] with r the
/// half-width per unit in `range` (or each actuator's range in the model), reproducibly from
/// `seed`, all reachable at the model's values; readings NaN.
Measurements random_configurations(const MeasurementModel& model, int count, std::uint64_t seed,
                                   const UnitValues& range);

/// The program's text and JSON renderings (`kincal observability`); `extra` holds a caller's
/// own sections (the program's --sensitivity), placed after the analysis.
std::string observability_text(const ObservabilityResult& result);
nlohmann::ordered_json observability_json(const ObservabilityResult& result,
                                          const nlohmann::ordered_json& extra);

}  // namespace kincal
