// An estimate mapped to the branch nearest nominal, when the map is exact
// (equivalent_solutions.hpp).
#include "kincal/framework/calibration/equivalent_solutions.hpp"

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <limits>

#include "kincal/framework/kinematics/units.hpp"

namespace kincal {

namespace {

// Predicted - measured at evenly spaced configurations (at most 2000), NaN-free entries
// only; empty when some configuration cannot be predicted.
constexpr int kCheckedConfigurations = 2000;

bool residuals_at(const CalibrationProblem& problem, const VectorXd& full, VectorXd& r) {
  const Measurements& data = problem.data();
  const int stride =
      std::max(1, (data.size() + kCheckedConfigurations - 1) / kCheckedConfigurations);
  std::vector<int> rows;
  for (int c = 0; c < data.size(); c += stride) rows.push_back(c);
  Measurements sample;
  sample.actuators = data.actuators(rows, Eigen::all);
  sample.readings = data.readings(rows, Eigen::all);
  const CalibrationProblem checked(problem.model_ptr(), sample, full, {});
  std::string why;
  if (!checked.evaluate(VectorXd(), &r, nullptr, &why)) return false;
  // Unwhitened, so that the tolerance is in the readings' units.
  const VectorXd& std = problem.model().reading_std();
  const int k = problem.model().num_readings();
  for (Eigen::Index i = 0; i < r.size(); ++i) r[i] *= std[i % k];
  return r.allFinite();
}

double largest_reading(const Measurements& data) {
  double largest = 0;
  for (Eigen::Index i = 0; i < data.readings.size(); ++i)
    if (std::isfinite(data.readings.data()[i]))
      largest = std::max(largest, std::abs(data.readings.data()[i]));
  return largest;
}

}  // namespace

VectorXd parameter_tolerances(const MeasurementModel& model, std::vector<bool>* assumed) {
  const int n = model.parameters().size();
  VectorXd tolerance(n);
  if (assumed) assumed->assign(static_cast<std::size_t>(n), false);
  for (int i = 0; i < n; ++i) {
    const Parameter& p = model.parameters()[i];
    if (std::isfinite(p.error_half_width) && p.error_half_width > 0) {
      tolerance[i] = p.error_half_width;
    } else if (p.prior_std > 0) {
      tolerance[i] = 3 * p.prior_std;
    } else {
      tolerance[i] = p.unit == kRadian ? 0.01 : 5.0;
      if (assumed) (*assumed)[static_cast<std::size_t>(i)] = true;
    }
  }
  return tolerance;
}

NominalBranch map_to_nominal_branch(const CalibrationProblem& problem, const VectorXd& x) {
  NominalBranch out;
  out.x = x;
  const MeasurementModel& model = problem.model();
  const VectorXd solved = problem.full_parameters(x);
  const VectorXd nominal = problem.full_parameters(problem.initial_free_parameters());
  VectorXd candidate = solved;
  std::vector<bool> free(static_cast<std::size_t>(model.parameters().size()), false);
  for (int i : problem.free_indices()) free[static_cast<std::size_t>(i)] = true;

  // Whole turns: each free angle on its branch nearest nominal; names what moved.
  const auto whole_turns = [&](VectorXd& values) {
    std::string turned;
    for (int i : problem.free_indices()) {
      if (model.parameters()[i].unit != kRadian) continue;
      const double near = nominal[i] + wrap_angle(values[i] - nominal[i]);
      if (std::abs(near - values[i]) > 1.0) {
        turned += (turned.empty() ? "" : ", ") + model.parameters()[i].name;
        values[i] = near;
      }
    }
    return turned;
  };
  const std::string turned = whole_turns(candidate);
  // The mechanism's discrete symmetries, among its free parameters, then whole turns again.
  const Mechanism& mechanism = model.mechanism();
  const int nm = mechanism.num_parameters();
  const std::vector<bool> changeable(free.begin(), free.begin() + nm);
  const VectorXd scale = parameter_tolerances(model).head(nm);
  VectorXd mapped;
  std::string what;
  VectorXd symmetric = candidate;
  const bool proposed = mechanism.nearer_equivalent(candidate.head(nm), nominal.head(nm),
                                                    changeable, scale, mapped, &what);
  std::string turned_after;
  if (proposed) {
    symmetric.head(nm) = mapped;
    turned_after = whole_turns(symmetric);
  }
  if (turned.empty() && !proposed) return out;

  VectorXd before;
  if (!residuals_at(problem, solved, before)) return out;
  const double tolerance =
      kEquivalentPredictionTolerance * std::max(1.0, largest_reading(problem.data()));
  const auto change_to = [&](const VectorXd& values) {
    for (int i = 0; i < values.size(); ++i)
      if (!free[static_cast<std::size_t>(i)] && values[i] != solved[i])
        return std::numeric_limits<double>::infinity();
    VectorXd r;
    if (!residuals_at(problem, values, r)) return std::numeric_limits<double>::infinity();
    return (r - before).cwiseAbs().maxCoeff();
  };
  if (proposed) {
    const double change = change_to(symmetric);
    if (change <= tolerance) {
      out.prediction_change = change;
      if (!turned.empty()) out.mapped.push_back("whole turns taken out of " + turned);
      out.mapped.push_back(what + (turned_after.empty()
                                       ? std::string()
                                       : ", then whole turns out of " + turned_after));
      out.x = problem.free_parameters(symmetric);
      return out;
    }
    char text[96];
    std::snprintf(text, sizeof text, " (not used: it changes a prediction by %.3g)", change);
    out.rejected = what + text;
  }
  if (turned.empty()) return out;
  const double change = change_to(candidate);
  if (!(change <= tolerance)) return out;
  out.prediction_change = change;
  out.mapped.push_back("whole turns taken out of " + turned);
  out.x = problem.free_parameters(candidate);
  return out;
}

}  // namespace kincal
