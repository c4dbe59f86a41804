#include "kincal/framework/analysis/identifiability_check.hpp"

#include "kincal/framework/base/triangular_factor.hpp"

#include <cmath>
#include <cstdio>
#include <stdexcept>

#include "kincal/framework/analysis/identifiability_words.hpp"
#include "kincal/framework/calibration/frame_turns.hpp"
#include "kincal/framework/calibration/prior_problem.hpp"
#include "kincal/framework/least_squares/uncertainty.hpp"

namespace kincal {

std::string describe_deficiency(const Identifiability& a) {
  char rcond[32];
  std::snprintf(rcond, sizeof rcond, "%g", a.rcond);
  std::string text;
  if (!a.unseen.empty()) {
    text = "no reading depends on free parameter(s)";
    for (const auto& name : a.unseen) text += " " + name;
    text += "; ";
  }
  text += "the data determine only " + std::to_string(a.numerical_rank) + " of " +
          std::to_string(a.num_parameters) + " free parameters (numerical rank, threshold " +
          rcond + " x largest scaled singular value)";
  if (a.frame_turns > 0)
    text += ", " + std::to_string(a.frame_turns) +
            " of the directions missing being turns of the whole setup, which change no fit "
            "(nothing measured fixes the measurement frame's orientation: a gauge freedom)";
  int shown = 0;
  for (const auto& c : a.combinations) {
    if (!c.null_space || shown == 3) continue;
    text += std::string(shown++ ? "; " : ": cannot separate ") + "[" + c.describe() + "]";
  }
  return text;
}

namespace {

// Beyond this, an entry of the whitened Jacobian (a derivative divided by its std) makes the
// sums of squares of the analysis and the solve overflow, or swamps every other entry: no
// real machine's derivatives are that large, but a std of 1e-300 makes them so.
constexpr double kMaxWhitenedJacobian = 1e100;

std::string number_text(double value) {
  char text[32];
  std::snprintf(text, sizeof text, "%g", value);
  return text;
}

// Which residual row `row` of J is, in words, with its std: a reading of a configuration or
// a constraint (framework/analysis/identifiability_check.hpp: the data's rows, then the
// constraints'). `fix` gets what to check.
std::string describe_row(const CalibrationProblem& problem, Eigen::Index row, std::string& fix) {
  const MeasurementModel& model = problem.model();
  const int readings = model.num_readings();
  const Eigen::Index data_rows = static_cast<Eigen::Index>(problem.data().size()) * readings;
  if (row < data_rows) {
    const int reading = static_cast<int>(row % readings);
    std::size_t sensor = 0;
    while (sensor + 1 < model.sensors().size() &&
           model.sensor_reading_offset(static_cast<int>(sensor) + 1) <= reading)
      ++sensor;
    fix = "the reading's std (reading_std, --noise-std) or the derivatives of sensor '" +
          model.sensors()[sensor]->name() + "' (type " + model.sensors()[sensor]->type() +
          ") and of mechanism type " + model.mechanism().type();
    return "configuration " + std::to_string(row / readings + 1) + ", reading '" +
           model.reading_names()[reading] + "' of sensor '" + model.sensors()[sensor]->name() +
           "' (std " + number_text(model.reading_std()[reading]) + " " +
           model.reading_units()[reading] + ")";
  }
  Eigen::Index first = data_rows;
  for (const auto& constraint : model.constraints()) {
    const int n = constraint->num_residuals();
    if (row < first + n) {
      const int k = static_cast<int>(row - first);
      fix = "the constraint's std or the derivatives of constraint type " + constraint->type();
      return "constraint " + constraint->type() + " " + constraint->label() + " (std " +
             number_text(constraint->residual_std()[k]) + " " + constraint->residual_units()[k] +
             ")";
    }
    first += n;
  }
  return "row " + std::to_string(row + 1);
}

// Throws std::invalid_argument naming the first entry of J (whitened: each row divided by its std)
// that is not finite or beyond kMaxWhitenedJacobian, with its reading or constraint and parameter:
// the analysis would otherwise see a parameter "no reading depends on", which blames the data.
void check_jacobian_usable(const std::string& where, const CalibrationProblem& problem,
                           const MatrixXd& J) {
  for (Eigen::Index c = 0; c < J.cols(); ++c)
    for (Eigen::Index r = 0; r < J.rows(); ++r) {
      const double value = J(r, c);
      if (std::isfinite(value) && std::abs(value) <= kMaxWhitenedJacobian) continue;
      std::string fix;
      const std::string row = describe_row(problem, r, fix);
      const std::string parameter = problem.parameter_names()[static_cast<std::size_t>(c)];
      if (!std::isfinite(value))
        throw std::invalid_argument(
            where + ": the whitened Jacobian (each derivative divided by its std) is " +
            number_text(value) + " at " + row + ", parameter " + parameter +
            ": a derivative or a std is not finite; check " + fix);
      throw std::invalid_argument(
          where + ": the whitened Jacobian (each derivative divided by its std) is " +
          number_text(value) + " at " + row + ", parameter " + parameter +
          ", beyond 1e100, where its squares overflow; check " + fix);
    }
}

}  // namespace

WhenRankDeficient when_rank_deficient(const MeasurementModel& model, bool allow_rank_deficient,
                                      bool explicit_mask) {
  const bool imported = !model.mechanism().identification_priority().empty() && !explicit_mask;
  return allow_rank_deficient || imported ? WhenRankDeficient::kFixDependent
                                          : WhenRankDeficient::kStop;
}

IdentifiabilityCheck check_identifiability(const std::string& where,
                                           const CalibrationProblem& problem, const MatrixXd& J_all,
                                           WhenRankDeficient when,
                                           const IdentifiabilityOptions& options,
                                           const std::string& remedy) {
  // The rows of the readings present and the constraint rows after the data's; no copy when
  // nothing is missing (J can have millions of rows).
  check_jacobian_usable(where, problem, J_all);
  const Measurements& data = problem.data();
  MatrixXd present;
  // Turns of the measurement frame that change no fit (sockets), with the same rows.
  MatrixXd turns = measurement_frame_turns(problem, problem.initial_free_parameters());
  // (Their constraint rows are zero: a J without constraint rows gets them without too.)
  if (turns.rows() >= J_all.rows())
    turns = turns.topRows(J_all.rows()).eval();
  else
    turns.resize(J_all.rows(), 0);
  const bool missing = data.num_present() < data.readings.size();
  if (missing) {
    std::vector<int> rows = data.present_rows();
    for (Eigen::Index i = data.readings.size(); i < J_all.rows(); ++i)
      rows.push_back(static_cast<int>(i));
    present = J_all(rows, Eigen::all);
    if (turns.cols()) turns = turns(rows, Eigen::all).eval();
  }
  const MatrixXd& J = missing ? present : J_all;
  IdentifiabilityCheck check;
  check.free = problem.free_indices();
  Identifiability& a = check.analysis;
  a = analyze_identifiability(J, problem.parameter_names(), options, turns);
  // With a prior, a direction the data cannot see is determined by the prior: what must
  // have full rank is the data stacked with the prior's rows.
  const Prior prior = model_prior(problem);
  const bool with_prior = prior.any();
  if (with_prior) {
    const VectorXd precision = prior.precision();
    add_prior(a, J, precision, data_share(J, precision), options, turns);
    if (a.rank_deficient() && !a.undetermined())
      check.notes.push_back("the data alone determine " + std::to_string(a.numerical_rank) +
                            " of " + std::to_string(a.num_parameters) +
                            " free parameters; the prior determines the rest");
  }
  if (!a.undetermined()) return check;
  // What determines the parameters: the data (through the triangular factor of [J turns],
  // which keeps every inner product the choice below uses, without copying J's rows),
  // stacked with the prior's rows.
  const Eigen::Index n = J.cols(), k = turns.cols();
  const MatrixXd factor = triangular_factor(J, turns);
  MatrixXd determining = factor.leftCols(n), determining_turns = factor.rightCols(k);
  if (with_prior) {
    const Eigen::Index rows = determining.rows();
    determining.conservativeResize(rows + n, n);
    determining.bottomRows(n) = prior.precision().cwiseSqrt().asDiagonal();
    determining_turns.conservativeResize(rows + n, k);
    determining_turns.bottomRows(n).setZero();
  }
  const MeasurementModel& model = problem.model();
  const std::vector<std::string> names = problem.parameter_names();
  const std::vector<int> keep =
      choose_identifiable(model, check.free, determining, options, determining_turns);
  const std::vector<DependentParameter> dependent =
      dependent_parameters(determining, names, keep, options, determining_turns);
  std::string deficiency = where + ": " + describe_deficiency(a) +
                           (with_prior ? " (the prior does not make up for it)" : "");
  if (when == WhenRankDeficient::kStop) {
    for (std::size_t k = 0; k < dependent.size() && k < 3; ++k)
      deficiency +=
          std::string(k ? "; " : "; null directions: ") + describe_dependent(dependent[k], model);
    if (dependent.size() > 3)
      deficiency += "; and " + std::to_string(dependent.size() - 3) + " more";
    throw std::invalid_argument(deficiency + "; " + remedy);
  }
  if (keep.empty())
    throw std::invalid_argument(
        deficiency +
        "; no free parameter is identifiable from this data, so there is nothing to "
        "solve for (--allow-rank-deficient needs at least one)");
  check.notes.push_back(
      "the data determine " + std::to_string(keep.size()) + " of the " +
      std::to_string(check.free.size()) + " free parameters; the other " +
      std::to_string(check.free.size() - keep.size()) +
      " are fixed at their model values (the table of fixed parameters says what each "
      "duplicates, a direction the data cannot see)");
  for (const DependentParameter& d : dependent) {
    check.null_directions.push_back(describe_dependent(d, model));
    check.fixed_effects.push_back(dependent_effect(d, model));
  }
  const std::vector<int> free = check.free;
  check.free.clear();
  std::size_t next = 0;
  for (std::size_t i = 0; i < free.size(); ++i) {
    if (next < keep.size() && keep[next] == static_cast<int>(i)) {
      check.free.push_back(free[i]);
      ++next;
    } else {
      check.fixed.push_back(names[i]);
    }
  }
  return check;
}

}  // namespace kincal
