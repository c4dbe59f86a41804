#pragma once
// The check calibrate and simulate make before solving: do the data (with the prior, when
// there is one) determine every free parameter at the starting values? A solver started on a
// problem they do not determine still stops, often with "converged", at one point of a
// valley of equally good ones: that is no estimate, and neither command presents it as one.

#include <string>
#include <vector>

#include "kincal/framework/analysis/identifiability.hpp"
#include "kincal/framework/calibration/calibration_problem.hpp"

namespace kincal {

/// One line naming what the data cannot determine: the parameters no reading depends on,
/// the numerical rank against the number of free parameters, and up to three combinations
/// the data cannot separate.
std::string describe_deficiency(const Identifiability& a);

struct IdentifiabilityCheck {
  Identifiability analysis;        ///< at the start; with the prior's rank when there is one
  std::vector<int> free;           ///< the parameters to solve for (indices in the model)
  std::vector<std::string> fixed;  ///< free parameters fixed because the data cannot see them
  /// For each of `fixed`, in words, what it duplicates (a null direction of the data), or
  /// that no reading depends on it (framework/analysis/identifiability_words.hpp).
  std::vector<std::string> null_directions;
  /// For each of `fixed`, the part of its null direction after its name (dependent_effect),
  /// for the aligned table of fixed parameters (fixed_parameters_table).
  std::vector<std::string> fixed_effects;
  /// What a user should read, in order (which parameters were fixed and why, what the prior
  /// determines), for the caller to show.
  std::vector<std::string> notes;
};

/// What to do when the data do not determine every free parameter.
enum class WhenRankDeficient {
  kStop,          ///< throw, naming the null directions (an explicit mask, the default)
  kFixDependent,  ///< fix the dependent parameters and say so (--allow-rank-deficient, or a
                  ///< mechanism with an identification_priority, an arm imported from a URDF,
                  ///< without --free/--fix: its error model is redundant on purpose,
                  ///< docs/theory.md)
};

/// Checks `problem` (its free parameters at their initial values; J its Jacobian there: the
/// data's rows, then any constraint rows), with the prior the model states on them
/// (model_prior), if any. Only the readings present are analysed, as in the report: a missing
/// one is a zero row of J that would count as a residual.
/// First, J must be usable: an entry that is not finite (a plug-in's NaN derivative) or beyond
/// 1e100 (a std of 1e-300 divides it) throws std::invalid_argument "<where>: the whitened Jacobian
/// ... is <value> at <the reading with its sensor, or the constraint, and its std>, parameter
/// <name>
/// ...; check <what>" instead of blaming the data for a parameter "no reading depends on".
/// When data and prior do not determine every free parameter: with kStop, throws
/// std::invalid_argument
/// "<where>: <describe_deficiency>; null directions: ...; <remedy>"; with kFixDependent,
/// keeps the identifiable subset (choose_identifiable), says in `notes` which parameters it
/// fixes at their model values and what each duplicates, and throws when no free parameter
/// is left to solve for.
IdentifiabilityCheck check_identifiability(const std::string& where,
                                           const CalibrationProblem& problem, const MatrixXd& J,
                                           WhenRankDeficient when,
                                           const IdentifiabilityOptions& options,
                                           const std::string& remedy);

/// kFixDependent when `allow_rank_deficient`, or when the model's mechanism states an
/// identification_priority (an arm imported from a URDF) and the user gave no --free/--fix
/// (`explicit_mask`); kStop otherwise.
WhenRankDeficient when_rank_deficient(const MeasurementModel& model, bool allow_rank_deficient,
                                      bool explicit_mask);

}  // namespace kincal
