#include "kincal/framework/analysis/identifiability.hpp"

#include "kincal/framework/base/triangular_factor.hpp"

#include <Eigen/QR>
#include <Eigen/SVD>
#include <algorithm>
#include <cmath>
#include <cstdio>
#include <limits>
#include <stdexcept>
#include <string>

namespace kincal {

namespace {

// A column this much shorter than the longest is rounding noise of a zero column (e.g. a
// rotation about an axis through the measured point, 1e-17 mm against lever arms of metres):
// scaled to unit norm it would look independent of everything, so it counts as zero.
constexpr double kZeroColumn = 1e-12;

// The column norms of J, those at the rounding noise of a zero column (kZeroColumn) set to 0.
VectorXd column_norms(const MatrixXd& J) {
  VectorXd norms = J.colwise().norm().transpose();
  const double longest = norms.size() ? norms.maxCoeff() : 0.0;
  for (int i = 0; i < norms.size(); ++i)
    if (norms[i] <= kZeroColumn * longest) norms[i] = 0;
  return norms;
}

// A D^-1 for the column norms D: unit-norm columns; zero columns stay zero.
MatrixXd scaled_by(MatrixXd A, const VectorXd& norms) {
  for (int i = 0; i < A.cols(); ++i) {
    if (norms[i] > 0)
      A.col(i) /= norms[i];
    else
      A.col(i).setZero();
  }
  return A;
}

// J D^-1 with unit-norm columns; zero columns (kZeroColumn) stay zero.
MatrixXd scale_columns(const MatrixXd& J, VectorXd& norms) {
  norms = column_norms(J);
  return scaled_by(J, norms);
}

// The scaled Jacobian with the turns of the measurement frame its columns reproduce
// projected out (identifiability.hpp). Built on the triangular factor of [J turns], which
// has the same inner products as J and the turns with n + k rows, so that a calibration with
// 10^6 readings is not copied. Empty `matrix` when no turn is reproduced: the caller then
// analyses J as it always did.
struct WithoutTurns {
  MatrixXd matrix;       ///< scaled, the reproduced turns projected out
  MatrixXd unprojected;  ///< scaled, before projecting them out
  VectorXd norms;        ///< the scaling D
  int turns = 0;         ///< how many were reproduced
};

// `scaled`'s columns span (its singular vectors above rcond of the largest) reproduces which
// of `turns`' directions to within rcond of their length? An orthonormal basis of those.
MatrixXd reproduced_turns(const MatrixXd& scaled, const MatrixXd& turns, double rcond) {
  if (scaled.cols() == 0 || turns.cols() == 0) return MatrixXd(scaled.rows(), 0);
  // The turns' own span (a turn of residuals that are all 0 is no direction).
  const Eigen::ColPivHouseholderQR<MatrixXd> tq(turns);
  const double largest = tq.matrixQR().rows() ? std::abs(tq.matrixQR()(0, 0)) : 0.0;
  int k = 0;
  while (k < std::min(tq.matrixQR().rows(), tq.matrixQR().cols()) &&
         std::abs(tq.matrixQR()(k, k)) > kZeroColumn * largest && largest > 0)
    ++k;
  if (k == 0) return MatrixXd(scaled.rows(), 0);
  const MatrixXd Q = tq.householderQ() * MatrixXd::Identity(turns.rows(), k);
  const Eigen::JacobiSVD<MatrixXd> svd(scaled, Eigen::ComputeThinU);
  const VectorXd& s = svd.singularValues();
  int r = 0;
  while (r < s.size() && s[r] > rcond * s[0]) ++r;
  // The parts of the turns outside that span: their singular values are the sines of the
  // angles between the two spans, small ones accurately (1 - cos^2 would lose them).
  const MatrixXd U = svd.matrixU().leftCols(r);
  const MatrixXd outside = Q - U * (U.transpose() * Q);
  const Eigen::JacobiSVD<MatrixXd> angles(outside, Eigen::ComputeFullV);
  const VectorXd& sines = angles.singularValues();
  int d = 0;
  while (d < k && sines[k - 1 - d] <= rcond) ++d;
  return Q * angles.matrixV().rightCols(d);
}

// The turns are directions of J's residuals: the same rows (none at all when there are none).
void check_turn_rows(const MatrixXd& J, const MatrixXd& turns) {
  if (turns.cols() > 0 && turns.rows() != J.rows())
    throw std::invalid_argument("identifiability: the turns have " + std::to_string(turns.rows()) +
                                " rows, the Jacobian " + std::to_string(J.rows()));
}

// `prior_sqrt_precision` (when non-null) stacks a prior's rows below J, with zero turns.
WithoutTurns without_reproduced_turns(const MatrixXd& J, const MatrixXd& turns, double rcond,
                                      const VectorXd* prior_sqrt_precision = nullptr) {
  WithoutTurns out;
  const Eigen::Index n = J.cols(), k = turns.cols();
  if (k == 0 || n == 0 || J.rows() == 0) return out;
  check_turn_rows(J, turns);
  const MatrixXd factor = triangular_factor(J, turns);
  MatrixXd compact = factor.leftCols(n), compact_turns = factor.rightCols(k);
  if (prior_sqrt_precision) {
    compact.conservativeResize(n + k + n, n);
    compact.bottomRows(n) = prior_sqrt_precision->asDiagonal();
    compact_turns.conservativeResize(n + k + n, k);
    compact_turns.bottomRows(n).setZero();
  }
  out.norms = prior_sqrt_precision ? column_norms(compact) : column_norms(J);
  out.unprojected = scaled_by(compact, out.norms);
  const MatrixXd basis = reproduced_turns(out.unprojected, compact_turns, rcond);
  out.turns = static_cast<int>(basis.cols());
  if (out.turns == 0) return out;
  out.matrix = out.unprojected - basis * (basis.transpose() * out.unprojected);
  return out;
}

// J and the turns side by side, compacted: the triangular factor of [J turns], split. What
// the subset choice and the duplicates below compute depends only on the inner products of
// these columns, so the factor stands in for J, and a calibration with 10^4-10^6 readings is
// analysed after one pass over its rows instead of column-pivoted passes over all of them.
struct Compact {
  MatrixXd J, turns;
};
Compact compacted(const MatrixXd& J, const MatrixXd& turns) {
  check_turn_rows(J, turns);
  const MatrixXd factor = triangular_factor(J, turns);
  return {factor.leftCols(J.cols()), factor.rightCols(turns.cols())};
}

// |c| to 9 significant digits, the key terms are sorted by: terms of the same size (a link's
// lever split between two joint offsets, +0.00255 and -0.00255) keep the model's order, not
// the one the last bits of a factorisation give.
double magnitude_key(double c) {
  const double a = std::abs(c);
  if (!(a > 0) || !std::isfinite(a)) return a;
  const double scale = std::pow(10.0, 8 - std::floor(std::log10(a)));
  return std::round(a * scale) / scale;
}

ParameterCombination make_combination(const VectorXd& v_scaled, const VectorXd& norms,
                                      const std::vector<std::string>& names, double s,
                                      bool null_space, double cutoff) {
  // Back to parameter units: scaled coordinate z_i = D_i p_i, so p_i = z_i / D_i. An unseen
  // parameter (D_i = 0) keeps its scaled coefficient.
  VectorXd v(v_scaled.size());
  for (int i = 0; i < v.size(); ++i) v[i] = norms[i] > 0 ? v_scaled[i] / norms[i] : v_scaled[i];
  v.normalize();
  // Sign convention: the largest term is positive, so the output is deterministic.
  Eigen::Index largest = 0;
  v.cwiseAbs().maxCoeff(&largest);
  if (v[largest] < 0) v = -v;
  ParameterCombination c;
  c.singular_value = s;
  c.null_space = null_space;
  const double max_abs = std::abs(v[largest]);
  for (int i = 0; i < v.size(); ++i)
    if (std::abs(v[i]) >= cutoff * max_abs) c.terms.emplace_back(names[i], v[i]);
  std::stable_sort(c.terms.begin(), c.terms.end(), [](const auto& a, const auto& b) {
    return magnitude_key(a.second) > magnitude_key(b.second);
  });
  return c;
}

}  // namespace

std::string ParameterCombination::describe() const {
  std::string out;
  char buf[32];
  for (const auto& [name, coefficient] : terms) {
    std::snprintf(buf, sizeof buf, "%+.3f ", coefficient);
    out += (out.empty() ? "" : " ") + std::string(buf) + name;
  }
  return out;
}

Identifiability analyze_identifiability(const MatrixXd& J, const std::vector<std::string>& names,
                                        const IdentifiabilityOptions& options,
                                        const MatrixXd& turns) {
  Identifiability a;
  a.num_residuals = static_cast<int>(J.rows());
  a.num_parameters = static_cast<int>(J.cols());
  a.names = names;
  a.rcond = options.rcond;
  const int n = a.num_parameters;
  if (n == 0) return a;
  if (a.num_residuals == 0) {  // no reading: nothing is seen (and Eigen's SVD needs rows)
    a.column_norms = a.singular_values = VectorXd::Zero(n);
    a.unseen = names;
    a.condition_number = std::numeric_limits<double>::infinity();
    return a;
  }

  // The SVDs below see only J^T J, so J's triangular factor stands in for it: a calibration
  // with 10^6 readings would otherwise copy its Jacobian several times over here.
  a.column_norms = column_norms(J);
  const WithoutTurns without = without_reproduced_turns(J, turns, options.rcond);
  a.frame_turns = without.turns;
  const MatrixXd scaled =
      without.turns ? without.matrix : scaled_by(triangular_factor(J), a.column_norms);
  for (int i = 0; i < n; ++i)
    if (a.column_norms[i] == 0) a.unseen.push_back(names[i]);

  // Full V: with fewer residuals than parameters the missing directions are null space too.
  const Eigen::JacobiSVD<MatrixXd> svd(scaled, Eigen::ComputeFullV);
  a.singular_values = VectorXd::Zero(n);
  a.singular_values.head(svd.singularValues().size()) = svd.singularValues();
  const VectorXd& s = a.singular_values;
  const double s_max = s[0];
  a.rank_threshold = std::max(a.num_residuals, n) * std::numeric_limits<double>::epsilon() * s_max;
  a.numerical_threshold = options.rcond * s_max;
  for (int i = 0; i < n; ++i) {
    a.rank += s[i] > a.rank_threshold;
    a.numerical_rank += s[i] > a.numerical_threshold;
  }

  // Singular values below the numerical-rank threshold are treated as zero everywhere else
  // (the rank, calibrate's refusal to solve, the null-space combinations); when they come
  // from an exact deficiency they are rounding noise of the SVD (1e-17), so ratios built
  // from them would be random numbers, not measures. A rank-deficient problem therefore
  // gets an infinite condition number and indices of 0, as if they were exactly 0.
  const double s_min = s[n - 1];
  a.condition_number = std::numeric_limits<double>::infinity();
  if (!a.rank_deficient() && a.rank == n && s_min > 0) {
    a.condition_number = s_max / s_min;
    double log_product = 0, inverse_squares = 0;
    for (int i = 0; i < n; ++i) {
      log_product += std::log(s[i]);
      inverse_squares += 1.0 / (s[i] * s[i]);
    }
    a.o1 = std::exp(log_product / n) / std::sqrt(static_cast<double>(a.num_residuals));
    a.o2 = s_min / s_max;
    a.o3 = s_min;
    a.o4 = s_min * s_min / s_max;
    a.o5 = 1.0 / inverse_squares;
  }

  // Combinations come from the seen columns only: an unseen parameter is reported by name
  // above, and leaving it in would mix it arbitrarily into the other null-space directions.
  std::vector<int> seen;
  for (int i = 0; i < n; ++i)
    if (a.column_norms[i] > 0) seen.push_back(i);
  if (seen.empty()) return a;
  const int n_seen = static_cast<int>(seen.size());
  MatrixXd scaled_seen(scaled.rows(), n_seen);
  VectorXd norms_seen(n_seen);
  std::vector<std::string> names_seen;
  for (int k = 0; k < n_seen; ++k) {
    scaled_seen.col(k) = scaled.col(seen[k]);
    norms_seen[k] = a.column_norms[seen[k]];
    names_seen.push_back(names[seen[k]]);
  }
  const Eigen::JacobiSVD<MatrixXd> svd_seen(scaled_seen, Eigen::ComputeFullV);
  VectorXd s_seen = VectorXd::Zero(n_seen);
  s_seen.head(svd_seen.singularValues().size()) = svd_seen.singularValues();
  for (int i = n_seen - 1; i >= 0; --i) {
    const bool null_space = !(s_seen[i] > a.numerical_threshold);
    if (!null_space && !(s_seen[i] < options.weak_ratio * s_max)) break;
    a.combinations.push_back(make_combination(svd_seen.matrixV().col(i), norms_seen, names_seen,
                                              s_seen[i], null_space, options.term_cutoff));
  }
  return a;
}

void add_prior(Identifiability& a, const MatrixXd& J, const VectorXd& precision,
               const VectorXd& data_share, const IdentifiabilityOptions& options,
               const MatrixXd& turns) {
  const int n = static_cast<int>(J.cols());
  a.data_share = data_share;
  a.numerical_rank_with_prior = 0;
  if (n == 0) return;  // Eigen's SVD of a matrix without columns is not defined
  // A turn the prior's rows do not see is still reproduced; one they pin is not.
  const VectorXd sqrt_precision = precision.cwiseSqrt();
  const WithoutTurns without = without_reproduced_turns(J, turns, options.rcond, &sqrt_precision);
  MatrixXd scaled;
  if (without.turns) {
    scaled = without.matrix;
  } else {
    const MatrixXd R = triangular_factor(J);  // as in analyze_identifiability
    MatrixXd stacked = MatrixXd::Zero(R.rows() + n, n);
    stacked.topRows(R.rows()) = R;
    stacked.bottomRows(n).diagonal() = sqrt_precision;
    VectorXd norms;
    scaled = scale_columns(stacked, norms);
  }
  const Eigen::JacobiSVD<MatrixXd> svd(scaled);
  const VectorXd& s = svd.singularValues();
  for (int i = 0; i < s.size(); ++i)
    a.numerical_rank_with_prior += s.size() && s[i] > options.rcond * s[0];
}

std::vector<int> identifiable_subset(const MatrixXd& J, const IdentifiabilityOptions& options,
                                     const MatrixXd& turns) {
  return identifiable_subset(J, std::vector<int>(), options, turns);
}

std::vector<int> identifiable_subset(const MatrixXd& J_all, const std::vector<int>& priority_given,
                                     const IdentifiabilityOptions& options,
                                     const MatrixXd& turns_all) {
  const int n = static_cast<int>(J_all.cols());
  if (n == 0 || J_all.rows() == 0) return {};
  const std::vector<int> priority =
      priority_given.empty() ? std::vector<int>(n, 0) : priority_given;
  const auto [J, turns] = compacted(J_all, turns_all);
  std::vector<std::string> names(n);
  const int rank = analyze_identifiability(J, names, options, turns).numerical_rank;
  const WithoutTurns without = without_reproduced_turns(J, turns, options.rcond);
  VectorXd norms;
  MatrixXd residual = without.turns ? without.matrix : scale_columns(J, norms);
  std::vector<bool> chosen(n, false);
  std::vector<int> keep;
  // Parts closer than this are equal: two columns that duplicate each other exactly differ
  // only by rounding, which must not decide which is kept; the first in the model's order is.
  const auto larger = [](double a, double b) { return a > b + kTiedParts; };
  while (static_cast<int>(keep.size()) < rank) {
    const VectorXd part = residual.colwise().norm().transpose();
    int best = -1;
    // The lowest class with a clearly independent column, then any column.
    int best_class = 0;
    for (int i = 0; i < n; ++i)
      if (!chosen[i] && part[i] > kPreferredPart &&
          (best < 0 || priority[i] < best_class ||
           (priority[i] == best_class && larger(part[i], part[best])))) {
        best = i;
        best_class = priority[i];
      }
    if (best < 0)
      for (int i = 0; i < n; ++i)
        if (!chosen[i] && (best < 0 || larger(part[i], part[best]))) best = i;
    if (best < 0 || !(part[best] > 0)) break;
    chosen[best] = true;
    keep.push_back(best);
    const VectorXd q = residual.col(best) / part[best];
    residual -= q * (q.transpose() * residual);
  }
  std::sort(keep.begin(), keep.end());
  return keep;
}

std::vector<DependentParameter> dependent_parameters(const MatrixXd& J_all,
                                                     const std::vector<std::string>& names,
                                                     const std::vector<int>& keep,
                                                     const IdentifiabilityOptions& options,
                                                     const MatrixXd& turns_all) {
  const auto [J, turns] = compacted(J_all, turns_all);
  const WithoutTurns without = without_reproduced_turns(J, turns, options.rcond);
  VectorXd norms = without.norms;
  const MatrixXd scaled = without.turns ? without.matrix : scale_columns(J, norms);
  MatrixXd kept(scaled.rows(), static_cast<Eigen::Index>(keep.size()));
  for (std::size_t k = 0; k < keep.size(); ++k)
    kept.col(static_cast<Eigen::Index>(k)) = scaled.col(keep[k]);
  // Eigen's decompositions do not take a matrix without columns: nothing kept, nothing to
  // express the others by (each is then described as it is).
  Eigen::ColPivHouseholderQR<MatrixXd> qr;
  if (!keep.empty()) qr.compute(kept);
  std::vector<DependentParameter> out;
  std::size_t next = 0;
  for (int i = 0; i < J.cols(); ++i) {
    if (next < keep.size() && keep[next] == i) {
      ++next;
      continue;
    }
    DependentParameter d;
    d.name = names[i];
    d.unseen = !(norms[i] > 0);
    if (!d.unseen && !keep.empty()) {
      // Scaled: column_i = sum_k c_k kept_k; in parameter units p_k = c_k D_i / D_k.
      const VectorXd c = qr.solve(VectorXd(scaled.col(i)));
      if (without.turns) {
        // What the kept columns leave of it before the turns were projected out: a turn.
        VectorXd left = without.unprojected.col(i);
        for (int k = 0; k < c.size(); ++k) left -= c[k] * without.unprojected.col(keep[k]);
        d.turn = left.norm() > options.rcond;
      }
      VectorXd coefficient(c.size());
      for (int k = 0; k < c.size(); ++k) coefficient[k] = c[k] * norms[i] / norms[keep[k]];
      const double largest = coefficient.cwiseAbs().maxCoeff();
      for (int k = 0; k < c.size(); ++k)
        if (std::abs(coefficient[k]) >= options.term_cutoff * largest && largest > 0)
          d.equivalent.emplace_back(names[keep[k]], coefficient[k]);
      std::stable_sort(d.equivalent.begin(), d.equivalent.end(), [](const auto& a, const auto& b) {
        return magnitude_key(a.second) > magnitude_key(b.second);
      });
    }
    out.push_back(d);
  }
  return out;
}

}  // namespace kincal
