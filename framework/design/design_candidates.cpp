// Experiment design, first stage: the singularity margin, the design setup (noise, scales,
// workspace) and the candidate configurations with their whitened reading rows.
#include "kincal/framework/design/experiment_design.hpp"

#include <Eigen/Cholesky>
#include <Eigen/Eigenvalues>
#include <Eigen/QR>
#include <Eigen/SVD>
#include <algorithm>
#include <cmath>
#include <limits>
#include <numeric>
#include <stdexcept>

#include "kincal/framework/base/random.hpp"
#include "kincal/framework/calibration/constrained_problem.hpp"
#include "kincal/framework/design/design_stages.hpp"

namespace kincal {

using namespace design_detail;

SingularityGauge::SingularityGauge(const MeasurementModel& model, const VectorXd& params)
    : model_(model), params_(params) {
  const Mechanism& mechanism = model.mechanism();
  home_.resize(mechanism.num_actuators());
  const InverseKinematicsResult ik =
      mechanism.home_actuators(params.head(mechanism.num_parameters()), home_);
  if (!ik.ok())
    throw std::invalid_argument("the model's home pose is not reachable: inverse kinematics " +
                                ik.describe());
  const ForwardKinematicsResult fk =
      mechanism.forward_kinematics(params.head(mechanism.num_parameters()), home_,
                                   mechanism.home_pose(), model.forward_kinematics_options());
  if (!fk.ok())
    throw std::invalid_argument("forward kinematics at the model's home configuration " +
                                fk.describe());
  Matrix6Xd J;
  // No moving actuator (every range 0) has no Jacobian to weigh: a block of a 6 x 0 matrix is
  // undefined behaviour in Eigen.
  if (actuator_jacobian(home_, fk.pose, J) && J.cols() > 0) {
    const double t = J.topRows<3>().norm(), r = J.bottomRows<3>().norm();
    rotation_length_ = r > 0 && t > 0 ? t / r : 1;
  }
  home_inverse_condition_ = inverse_condition(home_, fk.pose);
  if (!(home_inverse_condition_ > 0)) home_inverse_condition_ = 1;
}

bool SingularityGauge::actuator_jacobian(const ActuatorsRef& q, const Pose& pose,
                                         Matrix6Xd& J) const {
  const Mechanism& mechanism = model_.mechanism();
  const VectorXd& range = model_.actuator_ranges();
  const int na = mechanism.num_actuators();
  Matrix6Xd all(6, na);
  if (!mechanism.pose_jacobian_actuators(params_.head(mechanism.num_parameters()), q, pose,
                                         model_.forward_kinematics_options(), all))
    return false;
  int moving = 0;
  for (int i = 0; i < na; ++i) moving += range[i] > 0;
  J.resize(6, moving);
  int column = 0;
  for (int i = 0; i < na; ++i)
    if (range[i] > 0) J.col(column++) = all.col(i) * range[i];  // a fixed actuator has no say
  return true;
}

double SingularityGauge::inverse_condition(const ActuatorsRef& q, const Pose& pose) const {
  Matrix6Xd J;
  if (!actuator_jacobian(q, pose, J)) return 0;
  if (J.cols() == 0) return 1;
  J.bottomRows<3>() *= rotation_length_;
  // The singular values of J are the square roots of the largest min(6, columns) eigenvalues
  // of the fixed-size J J^T: cheaper than an SVD of J, and precise enough for a margin (it
  // loses only conditions beyond 1e8).
  const Matrix6d JJt = J * J.transpose();
  const Vector6d l = Eigen::SelfAdjointEigenSolver<Matrix6d>(JJt, Eigen::EigenvaluesOnly)
                         .eigenvalues();  // ascending
  const int k = static_cast<int>(std::min<Eigen::Index>(6, J.cols()));
  return l[5] > 0 ? std::sqrt(std::max(l[6 - k], 0.0) / l[5]) : 0;
}

double SingularityGauge::margin(const ActuatorsRef& q, const Pose& pose) const {
  return inverse_condition(q, pose) / home_inverse_condition_;
}

namespace {

// The normalised whitened rows of the readings of `sensor` from a full reading Jacobian.
void sensor_rows(const MeasurementModel& model, const DesignSetup& setup, const MatrixXd& J,
                 int sensor, Eigen::Ref<MatrixXd> out) {
  const int o = model.sensor_reading_offset(sensor);
  const int k = model.sensors()[sensor]->num_readings();
  for (int r = 0; r < k; ++r)
    for (std::size_t c = 0; c < setup.free_indices.size(); ++c)
      out(r, static_cast<int>(c)) = J(o + r, setup.free_indices[c]) *
                                    setup.scale[static_cast<int>(c)] / setup.noise_std[o + r];
}

}  // namespace

DesignSetup make_design_setup(const MeasurementModel& model, const DesignOptions& options,
                              const Measurements* existing) {
  DesignSetup s;
  s.free_indices = model.parameters().free_indices();
  const int n = static_cast<int>(s.free_indices.size());
  if (n == 0) throw std::invalid_argument("no free parameters: nothing to design for");
  s.scale = nominal_parameter_std(model, s.free_indices, options.default_error_mm,
                                  options.default_error_rad);
  s.noise_std = options.noise_std.size() ? options.noise_std : model.reading_std();
  if (s.noise_std.size() != model.num_readings() || !(s.noise_std.array() > 0).all() ||
      !s.noise_std.allFinite())
    throw std::invalid_argument("the reading noise std must be finite and > 0 for every reading");
  if (!(options.orientation_length >= 0) || !std::isfinite(options.orientation_length))
    throw std::invalid_argument("the orientation length must be finite and >= 0");
  s.base_information = MatrixXd::Zero(n, n);
  for (int c = 0; c < n; ++c) {
    const Parameter& p = model.parameters()[s.free_indices[c]];
    if (!p.has_prior()) continue;
    s.has_prior = true;
    s.base_information(c, c) += std::pow(s.scale[c] / p.prior_std, 2);
  }
  const VectorXd nominal = model.parameters().nominal_values();
  if (num_constraint_residuals(model) > 0) {
    // The model's parameter-only constraints (a known distance between fixtures) inform the
    // parameters whatever is measured, as the prior does: their whitened rows at the nominal
    // values join M0, normalised like the readings' rows. A problem without data gives them.
    Measurements none;
    none.actuators.resize(0, model.mechanism().num_actuators());
    none.readings.resize(0, model.num_readings());
    const CalibrationProblem at_nominal(
        std::shared_ptr<const MeasurementModel>(&model, [](const MeasurementModel*) {}), none,
        nominal, s.free_indices);
    VectorXd r;
    MatrixXd J;
    constraint_residuals(at_nominal, at_nominal.initial_free_parameters(), r, &J);
    const MatrixXd x = J * s.scale.asDiagonal();
    s.base_information += x.transpose() * x;
    s.constraint_rows = static_cast<int>(x.rows());
  }
  if (existing && existing->size() > 0) {
    auto ws = model.make_workspace();
    VectorXd readings(model.num_readings());
    MatrixXd J(model.num_readings(), model.num_parameters());
    Eigen::Ref<MatrixXd> J_ref(J);
    for (int row = 0; row < existing->size(); ++row) {
      const ForwardKinematicsResult fk =
          model.predict(nominal, existing->actuators.row(row).transpose(), readings, &J_ref, ws);
      if (!fk.ok())
        throw std::invalid_argument("existing data row " + std::to_string(row + 1) +
                                    ": forward kinematics at the nominal values " + fk.describe());
      for (int sensor = 0; sensor < static_cast<int>(model.sensors().size()); ++sensor) {
        const int o = model.sensor_reading_offset(sensor);
        const int k = model.sensors()[sensor]->num_readings();
        const auto measured = existing->readings.row(row).segment(o, k).array();
        if (measured.isNaN().all()) continue;
        MatrixXd x(k, n);
        sensor_rows(model, s, J, sensor, x);
        for (int r = 0; r < k; ++r)
          if (std::isnan(measured[r])) x.row(r).setZero();  // a point not seen informs nothing
        s.base_information += x.transpose() * x;
        s.existing_readings += static_cast<int>((!measured.isNaN()).count());
      }
    }
  }
  s.workspace = sample_workspace(model, nominal, s.free_indices, options.workspace_samples,
                                 derive_seed(options.seed, kWorkspaceStream));
  s.workspace_weight = MatrixXd::Zero(n, n);
  const double l2 = options.orientation_length * options.orientation_length;
  for (const Matrix6Xd& J : s.workspace.J_free) {
    const MatrixXd Jp = J.topRows<3>() * s.scale.asDiagonal();
    s.workspace_weight += Jp.transpose() * Jp;
    if (l2 > 0) {
      const MatrixXd Jr = J.bottomRows<3>() * s.scale.asDiagonal();
      s.workspace_weight += l2 * (Jr.transpose() * Jr);
    }
  }
  if (!s.workspace.J_free.empty()) s.workspace_weight /= double(s.workspace.J_free.size());
  return s;
}

DesignCandidates make_design_candidates(const MeasurementModel& model, const DesignSetup& setup,
                                        const DesignOptions& options) {
  const Mechanism& mechanism = model.mechanism();
  const int na = mechanism.num_actuators();
  const int n = static_cast<int>(setup.free_indices.size());
  const VectorXd nominal = model.parameters().nominal_values();
  const SingularityGauge gauge(model, nominal);
  const VectorXd& home = gauge.home_actuators();
  const VectorXd& range = model.actuator_ranges();
  const bool given = options.given.rows() > 0;
  if (given && options.given.cols() != na)
    throw std::invalid_argument("the candidate configurations have " +
                                std::to_string(options.given.cols()) + " columns; the model has " +
                                std::to_string(na) + " actuators");
  if (options.centre.size() != 0 && options.centre.size() != na)
    throw std::invalid_argument("the centre configuration has " +
                                std::to_string(options.centre.size()) + " values; the model has " +
                                std::to_string(na) + " actuators");
  DesignCandidates out;
  // The box the candidates are drawn from (not used when they are given).
  const bool box = options.box_low.size() == na && options.box_high.size() == na;
  const bool centred = options.centre.size() == na;
  const VectorXd& centre = centred ? options.centre : home;
  bool ranges_default = true, limited = false, all_limited = true;
  for (int a = 0; a < na; ++a) {
    const Actuator& actuator = mechanism.actuators()[static_cast<std::size_t>(a)];
    ranges_default = ranges_default && range[a] == actuator.default_range;
    const bool has_limits = std::isfinite(actuator.lower) && std::isfinite(actuator.upper);
    limited = limited || has_limits;
    if (actuator.commanded) all_limited = all_limited && has_limits;
  }
  const bool use_limits = !given && !box && !centred && ranges_default && limited && all_limited;
  VectorXd low(na), high(na);
  bool clipped = false;
  for (int a = 0; a < na; ++a) {
    const Actuator& actuator = mechanism.actuators()[static_cast<std::size_t>(a)];
    const bool has_limits = std::isfinite(actuator.lower) && std::isfinite(actuator.upper);
    if (box) {
      low[a] = options.box_low[a];
      high[a] = options.box_high[a];
    } else if (use_limits && has_limits) {
      low[a] = actuator.lower;
      high[a] = actuator.upper;
    } else {
      low[a] = centre[a] - range[a];
      high[a] = centre[a] + range[a];
    }
    if (has_limits && !given && (low[a] < actuator.lower || high[a] > actuator.upper)) {
      low[a] = std::max(low[a], actuator.lower);
      high[a] = std::min(high[a], actuator.upper);
      clipped = true;
      if (!(low[a] <= high[a]))
        throw std::invalid_argument("the candidates' box of " + actuator.name +
                                    " lies outside its limits [" + std::to_string(actuator.lower) +
                                    ", " + std::to_string(actuator.upper) + "] " + actuator.unit);
    }
  }
  out.region = given        ? "given"
               : box        ? "the box given"
               : use_limits ? "the joint limits"
               : centred    ? "the centre ± the actuator ranges"
                            : "home ± the actuator ranges";
  if (clipped) out.region += ", clipped to the joint limits";
  if (!given) {
    out.region_low = low;
    out.region_high = high;
  }
  // The draw of home ± range as it always was (the same candidates for the same seed).
  const bool legacy_draw = !given && !box && !use_limits && !centred && !clipped;
  const int num_corners = given ? 0 : na <= 12 ? (1 << na) : 0;
  const int total = given ? static_cast<int>(options.given.rows())
                          : num_corners + std::max(options.num_random, 0);

  const int num_sensors = static_cast<int>(model.sensors().size());
  std::vector<int> k(num_sensors);
  int rows_per_configuration = 0;
  for (int s = 0; s < num_sensors; ++s)
    rows_per_configuration += k[s] = model.sensors()[s]->num_readings();
  out.configurations.resize(total, na);
  out.margins.resize(total);
  out.rows.resize(static_cast<Eigen::Index>(total) * rows_per_configuration, n);
  out.row_offset.push_back(0);
  auto ws = model.make_workspace();
  VectorXd readings(model.num_readings()), q(na);
  MatrixXd J(model.num_readings(), model.num_parameters());
  Eigen::Ref<MatrixXd> J_ref(J);
  // Where a sensor can miss (a camera), a candidate holds only the readings it would take
  // there (the target in front of the camera, inside the image, not edge-on: what simulate
  // draws), and a configuration in which no sensor reads anything is no candidate.
  const bool check_view = model.sensors_can_miss();
  VectorXd seen(check_view ? model.num_readings() : 0);
  // A sensor with more readings than free parameters (a camera's 2 x points) is stored as the
  // n x n triangular factor of its information (X^T X = R^T R): the same information in fewer
  // rows, which the exchange and the bound then handle at a fraction of the cost.
  std::vector<MatrixXd> sensor_block(num_sensors);
  for (int s = 0; s < num_sensors; ++s) sensor_block[s].resize(k[s], n);
  Eigen::HouseholderQR<MatrixXd> qr;
  Random rng(derive_seed(options.seed, kCandidateStream));
  int kept = 0;
  for (int i = 0; i < total; ++i) {
    if (i % 256 == 0 && !keep_going(options, "candidates", i, total)) {
      out.stopped = true;
      break;
    }
    const bool corner = i < num_corners;
    if (given)
      q = options.given.row(i).transpose();
    else if (!legacy_draw)
      for (int a = 0; a < na; ++a)
        q[a] = corner ? ((i >> a) & 1 ? high[a] : low[a])
                      : low[a] + (high[a] - low[a]) * rng.uniform01();
    else
      for (int a = 0; a < na; ++a)
        q[a] = home[a] + (corner ? ((i >> a) & 1 ? range[a] : -range[a]) : rng.symmetric(range[a]));
    const ForwardKinematicsResult fk = model.predict(nominal, q, readings, &J_ref, ws);
    if (!fk.ok() || !J.allFinite()) {
      ++out.rejected_unreachable;
      continue;
    }
    const double margin = gauge.margin(q, fk.pose);
    if (!(margin >= options.min_singularity_margin)) {
      ++out.rejected_singular;
      continue;
    }
    if (check_view) {
      model.simulate_at_pose(nominal, fk.pose, seen);
      if (seen.array().isNaN().all()) {
        ++out.rejected_unseen;
        continue;
      }
    }
    if (corner) ++out.num_corners;
    out.configurations.row(kept) = q.transpose();
    out.margins[kept] = margin;
    for (int s = 0; s < num_sensors; ++s) {
      const int first = out.row_offset.back(), o = model.sensor_reading_offset(s);
      MatrixXd& X = sensor_block[s];
      sensor_rows(model, setup, J, s, X);
      int taken = k[s];
      if (check_view) {
        taken = 0;
        for (int r = 0; r < k[s]; ++r) {
          if (std::isnan(seen[o + r]))
            X.row(r).setZero();  // not seen: no information
          else
            ++taken;
        }
        if (taken == 0) continue;  // this sensor reads nothing here: no candidate
      }
      int stored = k[s];
      if (k[s] > n) {
        qr.compute(X);
        stored = n;
        out.rows.middleRows(first, n) = qr.matrixQR().topRows(n).triangularView<Eigen::Upper>();
      } else {
        out.rows.middleRows(first, k[s]) = X;
      }
      out.configuration.push_back(kept);
      out.sensor.push_back(s);
      out.readings.push_back(taken);
      out.row_offset.push_back(first + stored);
    }
    ++kept;
  }
  out.configurations.conservativeResize(kept, na);
  out.margins.conservativeResize(kept);
  out.rows.conservativeResize(out.row_offset.back(), n);
  return out;
}

}  // namespace kincal
