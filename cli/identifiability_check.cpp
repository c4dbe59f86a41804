#include "kincal/cli/identifiability_check.hpp"

#include <cstdio>

#include "kincal/cli/cli_util.hpp"
#include "kincal/cli/model_args.hpp"
#include "kincal/framework/prior_problem.hpp"
#include "kincal/framework/uncertainty.hpp"

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
  int shown = 0;
  for (const auto& c : a.combinations) {
    if (!c.null_space || shown == 3) continue;
    text += std::string(shown++ ? "; " : ": cannot separate ") + "[" + c.describe() + "]";
  }
  return text;
}

IdentifiabilityCheck check_identifiability(const std::string& command, const std::string& where,
                                           const CalibrationProblem& problem, const MatrixXd& J,
                                           bool allow_rank_deficient,
                                           const IdentifiabilityOptions& options,
                                           const std::string& remedy) {
  IdentifiabilityCheck check;
  check.free = problem.free_indices();
  Identifiability& a = check.analysis;
  a = analyze_identifiability(J, problem.parameter_names(), options);
  // With a prior, a direction the data cannot see is determined by the prior: what must
  // have full rank is the data stacked with the prior's rows.
  MatrixXd determining = J;
  const Prior prior = model_prior(problem);
  const bool with_prior = prior.any();
  if (with_prior) {
    const VectorXd precision = prior.precision();
    add_prior(a, J, precision, data_share(J, precision), options);
    determining.conservativeResize(J.rows() + J.cols(), J.cols());
    determining.bottomRows(J.cols()) = precision.cwiseSqrt().asDiagonal();
    if (a.rank_deficient() && !a.undetermined())
      note(command, "the data alone determine " + std::to_string(a.numerical_rank) + " of " +
                        std::to_string(a.num_parameters) +
                        " free parameters; the prior determines the rest");
  }
  if (!a.undetermined()) return check;
  const std::string deficiency = where + ": " + describe_deficiency(a) +
                                 (with_prior ? " (the prior does not make up for it)" : "");
  if (!allow_rank_deficient) throw CliError(deficiency + "; " + remedy);
  const std::vector<int> keep = identifiable_subset(determining, options);
  if (keep.empty())
    throw CliError(deficiency +
                   "; no free parameter is identifiable from this data, so there is nothing to "
                   "solve for (--allow-rank-deficient needs at least one)");
  const std::vector<int> free = check.free;
  const std::vector<std::string> names = problem.parameter_names();
  check.free.clear();
  std::size_t next = 0;
  for (std::size_t i = 0; i < free.size(); ++i) {
    if (next < keep.size() && keep[next] == static_cast<int>(i)) {
      check.free.push_back(free[i]);
      ++next;
    } else {
      check.fixed.push_back(names[i]);
      note(command, "fixing " + check.fixed.back() +
                        " at its model value (not identifiable from this data)");
    }
  }
  return check;
}

}  // namespace kincal::cli
