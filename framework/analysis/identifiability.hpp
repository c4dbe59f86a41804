#pragma once
// Identifiability of a calibration: what the identification Jacobian J (m residuals x n
// free parameters) says about which parameters the data can determine.
//
// Every figure is computed from the column-scaled Jacobian J D^-1, D = diag(|J_:,i|): each
// parameter's column has unit norm, so a parameter with a long lever arm does not look
// better determined merely because of its units or scale (Hollerbach & Wampler).
// With s_1 >= ... >= s_n its singular values and m the number of residuals:
//   condition number  s_1 / s_n
//   O1  (s_1 s_2 ... s_n)^(1/n) / sqrt(m)                  Borm & Menq, 1991
//   O2  s_n / s_1, the inverse condition number            Driels & Pathre, 1990
//   O3  s_n, the smallest singular value                   Nahvi, Hollerbach & Hayward, 1994
//   O4  s_n^2 / s_1, the noise amplification index          Nahvi & Hollerbach, 1996
//   O5  1 / sum_i (1 / s_i^2) = 1 / trace((D^-T J^T J D^-1)^-1)   A-optimality
// For each index larger is better. When J is rank deficient (numerical rank or rank below n,
// e.g. s_n = 1e-17, zero up to rounding), the condition number is infinite and all five
// indices are 0, whatever the SVD left in s_n.
//
// Turns of the measurement frame. Every function below also takes `turns` (m x k, rows as
// J's; empty: none): the residuals' change under motions of the whole setup that leave the
// cost as it is although J sees them (framework/calibration/frame_turns.hpp: a turn of a
// setup of sockets turns each socket's residual). Those of them the free parameters
// reproduce (their change of the residuals lies in the span of J's scaled columns to within
// rcond of its length) are a gauge freedom: their residual directions are projected out of
// the scaled Jacobian before anything is computed from it, so that the figures, the rank and
// the parameters kept are those of the Jacobian without them. When none is reproduced the
// analyses are exactly those without `turns`.

#include <string>
#include <vector>

#include "kincal/framework/base/types.hpp"

namespace kincal {

struct IdentifiabilityOptions {
  /// Numerical rank = number of scaled singular values above rcond * s_1. 1e-6: a direction
  /// a million times weaker than the best one amplifies gauge noise beyond any use.
  double rcond = 1e-6;
  /// Directions with s_i < weak_ratio * s_1 are also reported, as weakly determined.
  double weak_ratio = 1e-4;
  /// Terms whose |coefficient| is below this fraction of the largest one are left out of
  /// a combination's description.
  double term_cutoff = 0.1;
};

/// A direction in parameter space the data (nearly) cannot see: moving the parameters by
/// sum_k coefficient_k * e_k changes the readings by only singular_value (scaled units).
struct ParameterCombination {
  double singular_value = 0;  ///< scaled singular value of the direction
  bool null_space = false;    ///< below the rank threshold (not merely weak)
  /// (name, coefficient) of the significant terms, in parameter units (mm), largest first,
  /// normalised to unit length over all terms.
  std::vector<std::pair<std::string, double>> terms;
  /// e.g. "+0.707 leg1.offset -0.707 gauge.offset".
  std::string describe() const;
};

struct Identifiability {
  int num_residuals = 0;
  int num_parameters = 0;
  std::vector<std::string> names;
  VectorXd column_norms;           ///< |J_:,i|, the scaling D
  VectorXd singular_values;        ///< of the scaled Jacobian, descending
  int rank = 0;                    ///< singular values above rank_threshold
  double rank_threshold = 0;       ///< max(m, n) * eps * s_1 (machine precision)
  int numerical_rank = 0;          ///< singular values above numerical_threshold
  double numerical_threshold = 0;  ///< rcond * s_1
  double rcond = 0;
  double condition_number = 0;  ///< s_1 / s_n; +infinity when rank deficient
  double o1 = 0, o2 = 0, o3 = 0, o4 = 0, o5 = 0;
  /// Parameters whose column is zero: no reading depends on them.
  std::vector<std::string> unseen;
  /// How many of `turns` the free parameters reproduce (a gauge freedom), projected out of
  /// every figure above: each is one direction the data cannot determine.
  int frame_turns = 0;
  /// Null-space directions, then weak ones, weakest first.
  std::vector<ParameterCombination> combinations;

  /// With a prior (add_prior): the numerical rank of the whitened data stacked with the
  /// prior's rows (columns scaled the same way), and per parameter the share determined by
  /// the data (1 - posterior var / prior var; 1 for a parameter without a prior). -1 and
  /// empty without a prior.
  int numerical_rank_with_prior = -1;
  VectorXd data_share;
  bool has_prior() const { return numerical_rank_with_prior >= 0; }

  /// The data cannot determine every free parameter (numerical rank below n).
  bool rank_deficient() const { return numerical_rank < num_parameters; }
  /// Data and prior together cannot (without a prior: rank_deficient()).
  bool undetermined() const {
    return has_prior() ? numerical_rank_with_prior < num_parameters : rank_deficient();
  }
};

/// Analysis of J; `names` names its columns.
Identifiability analyze_identifiability(const MatrixXd& J, const std::vector<std::string>& names,
                                        const IdentifiabilityOptions& options = {},
                                        const MatrixXd& turns = MatrixXd());

/// Adds what a Gaussian prior of information diag(precision) (0 = none) changes: the rank of
/// [J; diag(sqrt(precision))] (J whitened) and `data_share` (e.g. from the posterior,
/// ParameterUncertainty::data_share, or data_share() at the stated noise). A direction the
/// data cannot see but the prior pins is then determined, by the prior.
void add_prior(Identifiability& a, const MatrixXd& J, const VectorXd& precision,
               const VectorXd& data_share, const IdentifiabilityOptions& options = {},
               const MatrixXd& turns = MatrixXd());

/// Columns of J that together are well determined: picked greedily from the scaled Jacobian
/// as a column-pivoted QR does, the column with the largest part outside the span of those
/// already picked first (of parts within kTiedParts, the first column), up to the numerical
/// rank. Returns the indices of the columns to keep, ascending. Fixing the others at their
/// current values solves the problem in an identifiable subspace. It works on J's
/// triangular factor (the same inner products), so its cost grows with J's rows only
/// through one QR pass.
std::vector<int> identifiable_subset(const MatrixXd& J, const IdentifiabilityOptions& options = {},
                                     const MatrixXd& turns = MatrixXd());

/// The same number of columns (the numerical rank), chosen class by class: `priority[i]` is
/// column i's class, lower first. Greedy Gram-Schmidt on the scaled columns: at each step the
/// column with the largest part outside the span of those already chosen, taken from the
/// lowest class that still has one with a part above `kPreferredPart` (so that of two columns
/// that duplicate each other the preferred one is kept), else from all. Empty `priority` =
/// one class. Returns the indices, ascending.
std::vector<int> identifiable_subset(const MatrixXd& J, const std::vector<int>& priority,
                                     const IdentifiabilityOptions& options = {},
                                     const MatrixXd& turns = MatrixXd());
/// The condition number's levels, the same in every report (calibrate's text, JSON and page,
/// observability's page): above kIllConditioned the weak directions amplify the sensor noise
/// noticeably; above kSeverelyIllConditioned (the paper's single-gauge cases, about 1e5)
/// some parameters are hardly determined.
inline constexpr double kIllConditioned = 1e3;
inline constexpr double kSeverelyIllConditioned = 1e5;

/// A column whose part outside the chosen span is below this (unit-norm columns) counts as a
/// duplicate when classes are compared.
inline constexpr double kPreferredPart = 1e-3;
/// Parts (unit-norm columns) this close are equal in the subset choice: columns that duplicate
/// each other exactly differ by rounding only (about 1e-15), and the model's order, not the
/// rounding of one factorisation or another, decides which is kept.
inline constexpr double kTiedParts = 1e-10;

/// A free parameter the data cannot tell from the others: its column of J is (up to the
/// numerical rank) a combination of the kept columns, so moving it by 1 changes the readings
/// as moving the kept parameters by `equivalent` does. That difference is a null-space
/// direction: +1 on `name`, -coefficient on each equivalent term.
struct DependentParameter {
  std::string name;
  bool unseen = false;  ///< no reading depends on it at all (its column is zero)
  /// It duplicates `equivalent` only together with a turn of the measurement frame (a gauge
  /// freedom): its column less the equivalent's has a part above rcond that is such a turn.
  bool turn = false;
  /// (name, coefficient) in parameter units, significant terms only (options.term_cutoff of
  /// the largest), largest first.
  std::vector<std::pair<std::string, double>> equivalent;
};

/// For each column of J not in `keep` (identifiable_subset), what it duplicates among the
/// kept columns (least squares on the scaled columns).
std::vector<DependentParameter> dependent_parameters(const MatrixXd& J,
                                                     const std::vector<std::string>& names,
                                                     const std::vector<int>& keep,
                                                     const IdentifiabilityOptions& options = {},
                                                     const MatrixXd& turns = MatrixXd());

}  // namespace kincal
