#include "kincal/cli/identifiability_check.hpp"

#include <cstdio>

#include "kincal/cli/cli_util.hpp"
#include "kincal/cli/identifiability_words.hpp"
#include "kincal/cli/model_args.hpp"
#include "kincal/framework/calibration/frame_turns.hpp"
#include "kincal/framework/calibration/prior_problem.hpp"
#include "kincal/framework/least_squares/uncertainty.hpp"

namespace kincal::cli {

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

WhenRankDeficient when_rank_deficient(const MeasurementModel& model, bool allow_rank_deficient,
                                      bool explicit_mask) {
  const bool imported = model.mechanism().type() == "urdf-arm" && !explicit_mask;
  return allow_rank_deficient || imported ? WhenRankDeficient::kFixDependent
                                          : WhenRankDeficient::kStop;
}

IdentifiabilityCheck check_identifiability(const std::string& command, const std::string& where,
                                           const CalibrationProblem& problem, const MatrixXd& J_all,
                                           WhenRankDeficient when,
                                           const IdentifiabilityOptions& options,
                                           const std::string& remedy) {
  // The rows of the readings present and the constraint rows after the data's; no copy when
  // nothing is missing (J can have millions of rows).
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
  MatrixXd determining = J;
  MatrixXd determining_turns = turns;
  const Prior prior = model_prior(problem);
  const bool with_prior = prior.any();
  if (with_prior) {
    const VectorXd precision = prior.precision();
    add_prior(a, J, precision, data_share(J, precision), options, turns);
    determining.conservativeResize(J.rows() + J.cols(), J.cols());
    determining.bottomRows(J.cols()) = precision.cwiseSqrt().asDiagonal();
    if (turns.cols()) {
      determining_turns.conservativeResize(J.rows() + J.cols(), turns.cols());
      determining_turns.bottomRows(J.cols()).setZero();
    }
    if (a.rank_deficient() && !a.undetermined())
      note(command, "the data alone determine " + std::to_string(a.numerical_rank) + " of " +
                        std::to_string(a.num_parameters) +
                        " free parameters; the prior determines the rest");
  }
  if (!a.undetermined()) return check;
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
    throw CliError(deficiency + "; " + remedy);
  }
  if (keep.empty())
    throw CliError(deficiency +
                   "; no free parameter is identifiable from this data, so there is nothing to "
                   "solve for (--allow-rank-deficient needs at least one)");
  note(command, "the data determine " + std::to_string(keep.size()) + " of the " +
                    std::to_string(check.free.size()) +
                    " free parameters; fixing the others at their model values (each named "
                    "with what it duplicates, a null direction of the data):");
  for (const DependentParameter& d : dependent) {
    check.null_directions.push_back(describe_dependent(d, model));
    note(command, "  " + check.null_directions.back());
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

}  // namespace kincal::cli
