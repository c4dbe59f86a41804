#include "kincal/framework/analysis/pose_accuracy.hpp"

#include <Eigen/Eigenvalues>
#include <algorithm>
#include <cmath>
#include <cstdio>
#include <limits>
#include <sstream>
#include <stdexcept>

#include "kincal/framework/base/random.hpp"
#include "kincal/framework/kinematics/units.hpp"

namespace kincal {

WorkspaceSamples sample_workspace(const MeasurementModel& model, const VectorXd& params,
                                  const std::vector<int>& free_indices, int count,
                                  std::uint64_t seed) {
  const Mechanism& mechanism = model.mechanism();
  const int n_mech = mechanism.num_parameters();
  const int na = mechanism.num_actuators();
  const VectorXd nominal = model.parameters().nominal_values();
  VectorXd home(na);
  const InverseKinematicsResult home_ik = mechanism.home_actuators(nominal.head(n_mech), home);
  if (!home_ik.ok())
    throw std::invalid_argument("the model's home pose is not reachable: inverse kinematics " +
                                home_ik.describe());
  const VectorXd& range = model.actuator_ranges();
  const auto mech_params = params.head(n_mech);

  WorkspaceSamples out;
  out.actuators.resize(std::max(count, 0), na);
  out.J_free.assign(std::max(count, 0), Matrix6Xd::Zero(6, free_indices.size()));
  Random rng(seed);
  Matrix6Xd J_pose(6, n_mech);
  VectorXd q(na);
  const long long max_attempts = 1000LL * std::max(count, 1);
  long long attempts = 0;
  for (int s = 0; s < count;) {
    if (++attempts > max_attempts)
      throw std::runtime_error(
          "could not draw workspace configurations: forward kinematics keeps failing in the "
          "configuration box (is the configuration range too large?)");
    for (int i = 0; i < na; ++i) q[i] = home[i] + rng.symmetric(range[i]);
    const ForwardKinematicsResult fk = mechanism.forward_kinematics(
        mech_params, q, mechanism.home_pose(), model.forward_kinematics_options());
    if (!fk.ok()) continue;
    mechanism.pose_jacobian_params(mech_params, q, fk.pose, J_pose);
    for (std::size_t c = 0; c < free_indices.size(); ++c)
      if (free_indices[c] < n_mech) out.J_free[s].col(c) = J_pose.col(free_indices[c]);
    out.actuators.row(s) = q.transpose();
    ++s;
  }
  return out;
}

namespace {

// P(a, x), the regularised lower incomplete gamma function, by its power series (converges
// for every x; the quantiles asked for here have x of a few tens at most).
double regularized_gamma_p(double a, double x) {
  if (x <= 0) return 0;
  double term = 1.0 / a, sum = term;
  for (int n = 1; n < 10000; ++n) {
    term *= x / (a + n);
    sum += term;
    if (term < sum * 1e-16) break;
  }
  return std::min(1.0, std::exp(-x + a * std::log(x) - std::lgamma(a)) * sum);
}

}  // namespace

double chi_square_quantile(double probability, double nu) {
  if (!(nu > 0) || !(probability >= 0 && probability < 1))
    return std::numeric_limits<double>::quiet_NaN();
  double lo = 0, hi = nu + 20 * std::sqrt(2 * nu) + 50;
  for (int i = 0; i < 200 && hi - lo > 1e-13 * hi; ++i) {
    const double mid = 0.5 * (lo + hi);
    (regularized_gamma_p(0.5 * nu, 0.5 * mid) < probability ? lo : hi) = mid;
  }
  return 0.5 * (lo + hi);
}

double error_norm_quantile(const Matrix3d& covariance, double probability) {
  if (!covariance.allFinite()) return std::numeric_limits<double>::quiet_NaN();
  const Vector3d l = Eigen::SelfAdjointEigenSolver<Matrix3d>(covariance, Eigen::EigenvaluesOnly)
                         .eigenvalues()
                         .cwiseMax(0.0);
  const double sum = l.sum(), sum_sq = l.squaredNorm();
  if (!(sum > 0)) return 0;
  const double c = sum_sq / sum, nu = sum * sum / sum_sq;
  return std::sqrt(c * chi_square_quantile(probability, nu));
}

PoseErrorPrediction predict_pose_errors(const WorkspaceSamples& samples,
                                        const MatrixXd& covariance) {
  PoseErrorPrediction p;
  p.samples = static_cast<int>(samples.J_free.size());
  if (p.samples == 0) return p;
  if (!covariance.allFinite()) {
    const double nan = std::numeric_limits<double>::quiet_NaN();
    p.position_rms = p.position_mean_1sigma = p.position_max_1sigma = p.position_mean_95 =
        p.position_max_95 = nan;
    p.orientation_rms = p.orientation_mean_1sigma = p.orientation_max_1sigma =
        p.orientation_mean_95 = p.orientation_max_95 = nan;
    return p;
  }
  double position_ms = 0, orientation_ms = 0;
  for (const Matrix6Xd& J : samples.J_free) {
    const Matrix6d pose_cov = J * covariance * J.transpose();
    const Matrix3d P = pose_cov.topLeftCorner<3, 3>(), R = pose_cov.bottomRightCorner<3, 3>();
    const double p1 = std::sqrt(std::max(P.trace(), 0.0));
    const double r1 = std::sqrt(std::max(R.trace(), 0.0));
    const double p95 = error_norm_quantile(P, 0.95), r95 = error_norm_quantile(R, 0.95);
    p.position_1sigma.push_back(p1);
    position_ms += p1 * p1;
    orientation_ms += r1 * r1;
    p.position_mean_1sigma += p1;
    p.position_max_1sigma = std::max(p.position_max_1sigma, p1);
    p.position_mean_95 += p95;
    p.position_max_95 = std::max(p.position_max_95, p95);
    p.orientation_mean_1sigma += r1;
    p.orientation_max_1sigma = std::max(p.orientation_max_1sigma, r1);
    p.orientation_mean_95 += r95;
    p.orientation_max_95 = std::max(p.orientation_max_95, r95);
  }
  const double n = p.samples;
  p.position_rms = std::sqrt(position_ms / n);
  p.orientation_rms = std::sqrt(orientation_ms / n);
  p.position_mean_1sigma /= n;
  p.position_mean_95 /= n;
  p.orientation_mean_1sigma /= n;
  p.orientation_mean_95 /= n;
  return p;
}

VectorXd nominal_parameter_std(const MeasurementModel& model, const std::vector<int>& free_indices,
                               double default_error_mm, double default_error_rad) {
  VectorXd std(free_indices.size());
  for (std::size_t c = 0; c < free_indices.size(); ++c) {
    const Parameter& p = model.parameters()[free_indices[c]];
    const double e = !std::isnan(p.error_half_width) ? p.error_half_width
                     : p.unit == kRadian             ? default_error_rad
                                                     : default_error_mm;
    std[static_cast<int>(c)] = p.has_prior() ? p.prior_std : e / std::sqrt(3.0);
  }
  return std;
}

namespace {

nlohmann::ordered_json number(double v) {
  return std::isfinite(v) ? nlohmann::ordered_json(v) : nlohmann::ordered_json();
}

}  // namespace

nlohmann::ordered_json to_json(const PoseErrorPrediction& p) {
  return {{"position_rms_mm", number(p.position_rms)},
          {"position_mean_1sigma_mm", number(p.position_mean_1sigma)},
          {"position_max_1sigma_mm", number(p.position_max_1sigma)},
          {"position_mean_95_mm", number(p.position_mean_95)},
          {"position_max_95_mm", number(p.position_max_95)},
          {"orientation_rms_rad", number(p.orientation_rms)},
          {"orientation_mean_1sigma_rad", number(p.orientation_mean_1sigma)},
          {"orientation_max_1sigma_rad", number(p.orientation_max_1sigma)},
          {"orientation_mean_95_rad", number(p.orientation_mean_95)},
          {"orientation_max_95_rad", number(p.orientation_max_95)}};
}

AccuracyComparison compare_with_nominal(const MeasurementModel& model, const VectorXd& params,
                                        const std::vector<int>& free_indices,
                                        const MatrixXd& covariance, int samples,
                                        std::uint64_t seed) {
  AccuracyComparison a;
  try {
    const WorkspaceSamples w = sample_workspace(model, params, free_indices, samples, seed);
    a.calibrated = predict_pose_errors(w, covariance);
    const VectorXd std = nominal_parameter_std(model, free_indices);
    a.nominal = predict_pose_errors(w, MatrixXd(std.array().square().matrix().asDiagonal()));
  } catch (const std::exception& e) {
    a.why_not = e.what();
    return a;
  }
  if (!covariance.allFinite()) {
    a.why_not = "the estimate has no covariance (no degrees of freedom, or a singular fit)";
    return a;
  }
  if (a.nominal.position_rms == 0 && a.calibrated.position_rms == 0 &&
      a.nominal.orientation_rms == 0 && a.calibrated.orientation_rms == 0) {
    // A camera's or a tracker's own parameters only, on a mechanism known by its reported
    // poses (flange-pose): nothing calibrated moves the end effector, nothing to compare.
    a.why_not = "no free parameter moves the mechanism's pose";
    return a;
  }
  a.computed = true;
  a.expected_to_beat_nominal =
      a.calibrated.position_rms < a.nominal.position_rms &&
      (a.nominal.orientation_rms == 0 || a.calibrated.orientation_rms < a.nominal.orientation_rms);
  return a;
}

nlohmann::ordered_json to_json(const AccuracyComparison& a) {
  nlohmann::ordered_json out;
  out["computed"] = a.computed;
  if (!a.computed) {
    out["why_not"] = a.why_not;
    return out;
  }
  out["workspace_samples"] = a.calibrated.samples;
  out["where"] =
      "the mechanism's end-effector frame at configurations drawn in the actuator box around "
      "home, from the free mechanism parameters";
  out["calibrated"] = to_json(a.calibrated);
  out["nominal"] = to_json(a.nominal);
  out["nominal_from"] =
      "the assumed spread of the parameters (prior_std, else param_error / sqrt 3, else 5 mm "
      "and 0.01 rad / sqrt 3), not measured";
  out["expected_to_beat_nominal"] = a.expected_to_beat_nominal;
  // Per workspace sample, for the plot of the error over the workspace (HTML page).
  nlohmann::ordered_json calibrated = nlohmann::ordered_json::array(),
                         nominal = nlohmann::ordered_json::array();
  for (double v : a.calibrated.position_1sigma) calibrated.push_back(number(v));
  for (double v : a.nominal.position_1sigma) nominal.push_back(number(v));
  out["position_1sigma_mm_per_sample"] = {{"calibrated", calibrated}, {"nominal", nominal}};
  return out;
}

std::string to_text(const AccuracyComparison& a) {
  if (!a.computed) return "predicted pose error: not computed (" + a.why_not + ")\n";
  std::ostringstream out;
  char buf[200];
  out << "predicted pose error over the workspace (" << a.calibrated.samples
      << " configurations in the actuator box; 1 sigma = RMS, 95 % quantile):\n";
  const auto line = [&](const char* label, const PoseErrorPrediction& p) {
    std::snprintf(buf, sizeof buf,
                  "  %-10s position mean %.4g / max %.4g mm (95 %%: mean %.4g / max %.4g), "
                  "orientation mean %.3g / max %.3g rad (95 %%: mean %.3g / max %.3g)\n",
                  label, p.position_mean_1sigma, p.position_max_1sigma, p.position_mean_95,
                  p.position_max_95, p.orientation_mean_1sigma, p.orientation_max_1sigma,
                  p.orientation_mean_95, p.orientation_max_95);
    out << buf;
  };
  line("calibrated", a.calibrated);
  line("nominal", a.nominal);
  if (!a.expected_to_beat_nominal)
    out << "calibration is NOT expected to beat the nominal model: the data determine the "
           "parameters less well than their nominal values are known (measure more or better "
           "chosen configurations: kincal design; or state the prior knowledge)\n";
  return out.str();
}

}  // namespace kincal
