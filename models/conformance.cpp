#include "kincal/models/conformance.hpp"

#include <algorithm>
#include <cmath>
#include <limits>
#include <set>
#include <sstream>

#include "kincal/framework/calibration/simulation.hpp"
#include "kincal/framework/kinematics/units.hpp"
#include "kincal/models/model_io.hpp"

namespace kincal {

namespace {

constexpr double kNaN = std::numeric_limits<double>::quiet_NaN();

ConformanceCheck failed(const std::string& name, const std::string& why, double tolerance = kNaN) {
  return {name, false, kNaN, tolerance, why};
}

// Runs `body`, turning an exception from a model's code into that check's failure.
template <class Body>
void guarded(std::vector<ConformanceCheck>& out, const std::string& name, Body body) {
  try {
    body();
  } catch (const std::exception& e) {
    out.push_back(failed(name, std::string("threw: ") + e.what()));
  }
}

// A noise-free scenario as `kincal simulate` draws it, without validation poses.
Scenario scenario_of(const ModelFactory& make, std::uint64_t seed) {
  ScenarioOptions options;
  options.num_validation = 0;
  options.seed = seed;
  return make_scenario(make(), options);
}

// [t1 - t0; log(R1 R0^T)]: the perturbation taking pose `from` to pose `to` (pose.hpp).
Vector6d pose_difference(const Pose& from, const Pose& to) {
  Vector6d d;
  d << to.translation - from.translation, log_so3(to.rotation * from.rotation.transpose());
  return d;
}

// The worst of several checks of one Jacobian (one per configuration) as one verdict.
ConformanceCheck worst_of(const std::string& name, const std::vector<ConformanceCheck>& parts) {
  ConformanceCheck out{name, true, 0, parts.empty() ? kNaN : parts.front().tolerance, ""};
  for (const auto& p : parts) {
    out.passed = out.passed && p.passed;
    if (out.detail.empty() || !(p.worst <= out.worst)) {  // NaN counts as the worst
      out.worst = p.worst;
      out.detail = p.detail;
    }
  }
  return out;
}

}  // namespace

MatrixXd numerical_jacobian(const std::function<VectorXd(const VectorXd&)>& f, const VectorXd& x,
                            double h) {
  const VectorXd f0 = f(x);
  MatrixXd J(f0.size(), x.size());
  for (int i = 0; i < x.size(); ++i) {
    VectorXd xp = x, xm = x;
    xp[i] += h;
    xm[i] -= h;
    J.col(i) = (f(xp) - f(xm)) / (2 * h);
  }
  return J;
}

ConformanceCheck compare_jacobians(const std::string& name, const MatrixXd& analytic,
                                   const MatrixXd& numeric, double tolerance,
                                   const std::vector<std::string>& column_names) {
  if (analytic.rows() != numeric.rows() || analytic.cols() != numeric.cols()) {
    std::ostringstream os;
    os << "size " << analytic.rows() << " x " << analytic.cols() << ", finite differences give "
       << numeric.rows() << " x " << numeric.cols();
    return failed(name, os.str(), tolerance);
  }
  double worst = 0;
  int wr = 0, wc = 0;
  for (int r = 0; r < analytic.rows() && !std::isnan(worst); ++r)
    for (int c = 0; c < analytic.cols() && !std::isnan(worst); ++c) {
      const double e = std::abs(analytic(r, c) - numeric(r, c)) / (1 + std::abs(numeric(r, c)));
      if (!(e <= worst)) worst = e, wr = r, wc = c;  // the first NaN is the worst, and stays
    }
  std::ostringstream os;
  os << "worst at row " << wr << ", column " << wc;
  if (wc < static_cast<int>(column_names.size())) os << " '" << column_names[wc] << "'";
  if (analytic.size() > 0)
    os << ": analytic " << analytic(wr, wc) << ", finite differences " << numeric(wr, wc);
  return {name, worst <= tolerance, worst, tolerance, os.str()};
}

std::vector<ConformanceCheck> check_model_file(const ModelFactory& make) {
  std::vector<ConformanceCheck> out;
  guarded(out, "model file round trip", [&] {
    const auto model = make();
    const VectorXd values = model->parameters().nominal_values();
    const auto first = model_to_json(*model, values);
    const auto back = model_from_json(first, "(round trip)");
    std::string why;
    double worst = 0;
    if (model_to_json(*back, back->parameters().nominal_values()).dump() != first.dump())
      why = "the file written from the model read back differs from the first";
    if (back->num_parameters() != model->num_parameters()) {
      why = "read back with " + std::to_string(back->num_parameters()) + " parameters, not " +
            std::to_string(model->num_parameters());
    } else {
      for (int i = 0; i < model->num_parameters() && why.empty(); ++i) {
        const Parameter &a = model->parameters()[i], &b = back->parameters()[i];
        if (a.name != b.name || a.unit != b.unit || a.free != b.free)
          why = "parameter " + std::to_string(i) + " '" + a.name + "' reads back as '" + b.name +
                "' (" + b.unit + (b.free ? ", free" : ", fixed") + ")";
        // Angles pass through degrees in the file: equal to rounding.
        const double d = std::abs(a.nominal - b.nominal) / (1 + std::abs(a.nominal));
        if (!(d <= worst)) {
          worst = d;
          if (!(d <= 1e-12)) why = a.name + " reads back as " + std::to_string(b.nominal);
        }
      }
    }
    if (why.empty() && back->mechanism().actuator_names() != model->mechanism().actuator_names())
      why = "the actuator names differ after the round trip";
    if (why.empty() && back->reading_names() != model->reading_names())
      why = "the reading names differ after the round trip";
    out.push_back({"model file round trip", why.empty(), worst, 1e-12,
                   why.empty() ? "values equal to rounding" : why});
  });
  guarded(out, "units declared", [&] {
    const auto model = make();
    std::string why;
    for (const auto& p : model->parameters().all())
      if (!is_known_unit(p.unit))
        why = "parameter " + p.name + " has unit '" + p.unit + "', not a base unit of the registry";
    for (const auto& a : model->mechanism().actuators()) {
      if (!is_known_unit(a.unit)) why = "actuator " + a.name + " has unit '" + a.unit + "'";
      if (!(a.default_range > 0)) why = "actuator " + a.name + " has no default range > 0";
    }
    const auto units = model->reading_units();
    if (static_cast<int>(units.size()) != model->num_readings())
      why = "reading_units() gives " + std::to_string(units.size()) + " units for " +
            std::to_string(model->num_readings()) + " readings";
    for (const auto& u : units)
      if (!is_known_unit(u)) why = "a reading has unit '" + u + "'";
    out.push_back({"units declared", why.empty(), 0, 0,
                   why.empty() ? "base units of the registry (mm, rad, px, a plug-in's)" : why});
  });
  return out;
}

namespace {

// A mechanism Jacobian against central differences of forward kinematics at the first four
// configurations of the scenario drawn with `seed`: J_pose_params (`wrt_params`; forward
// kinematics from home, as a calibration runs it) or J_pose_actuators (from the pose itself,
// with a larger step, as experiment design's singularity margin uses it).
ConformanceCheck pose_jacobian_check(const ModelFactory& make, std::uint64_t seed, bool wrt_params,
                                     const std::string& name) {
  const Scenario s = scenario_of(make, seed);
  const Mechanism& mechanism = s.model->mechanism();
  const VectorXd params = s.truth.head(mechanism.num_parameters());
  const auto fk_options = s.model->forward_kinematics_options();
  std::vector<ConformanceCheck> parts;
  for (int j = 0; j < std::min(4, s.calibration.size()); ++j) {
    const VectorXd q = s.calibration.actuators.row(j).transpose();
    const auto fk = mechanism.forward_kinematics(params, q, mechanism.home_pose(), fk_options);
    if (!fk.ok()) throw std::runtime_error("forward kinematics: " + fk.describe());
    Matrix6Xd J(6, wrt_params ? mechanism.num_parameters() : mechanism.num_actuators());
    if (wrt_params)
      mechanism.pose_jacobian_params(params, q, fk.pose, J);
    else if (!mechanism.pose_jacobian_actuators(params, q, fk.pose, fk_options, J))
      throw std::runtime_error("pose_jacobian_actuators failed at configuration " +
                               std::to_string(j));
    std::string fk_failure;
    auto pose_at = [&](const VectorXd& moved) -> VectorXd {
      const auto at =
          wrt_params ? mechanism.forward_kinematics(moved, q, mechanism.home_pose(), fk_options)
                     : mechanism.forward_kinematics(params, moved, fk.pose, fk_options);
      if (!at.ok()) fk_failure = at.describe();
      return pose_difference(fk.pose, at.pose);
    };
    const MatrixXd numeric =
        numerical_jacobian(pose_at, wrt_params ? params : q, wrt_params ? 1e-6 : 1e-5);
    if (!fk_failure.empty()) throw std::runtime_error("forward kinematics: " + fk_failure);
    parts.push_back(
        compare_jacobians(name, J, numeric, 1e-6,
                          wrt_params ? s.model->parameters().names() : mechanism.actuator_names()));
    parts.back().detail = "configuration " + std::to_string(j) + ", " + parts.back().detail;
  }
  return worst_of(name, parts);
}

}  // namespace

std::vector<ConformanceCheck> check_mechanism_jacobians(const ModelFactory& make) {
  std::vector<ConformanceCheck> out;
  const std::string params_name = "J_pose_params of the mechanism";
  guarded(out, params_name,
          [&] { out.push_back(pose_jacobian_check(make, 3, true, params_name)); });
  // d pose / d q (experiment design's singularity margin).
  const std::string actuators_name = "J_pose_actuators of the mechanism";
  guarded(out, actuators_name,
          [&] { out.push_back(pose_jacobian_check(make, 5, false, actuators_name)); });
  return out;
}

std::vector<ConformanceCheck> check_sensor_jacobians(const ModelFactory& make) {
  std::vector<ConformanceCheck> out;
  guarded(out, "sensor Jacobians", [&] {
    const Scenario s = scenario_of(make, 4);
    const Mechanism& mechanism = s.model->mechanism();
    const auto fk = mechanism.forward_kinematics(
        s.truth.head(mechanism.num_parameters()), s.calibration.actuators.row(0).transpose(),
        mechanism.home_pose(), s.model->forward_kinematics_options());
    if (!fk.ok()) throw std::runtime_error("forward kinematics: " + fk.describe());
    for (std::size_t k = 0; k < s.model->sensors().size(); ++k) {
      const Sensor& sensor = *s.model->sensors()[k];
      const std::string of = " of sensor '" + sensor.name() + "' (" + sensor.type() + ")";
      const int n = sensor.num_readings();
      const VectorXd params = s.truth.segment(s.model->sensor_parameter_offset(static_cast<int>(k)),
                                              sensor.num_parameters());
      VectorXd reading(n);
      MatrixXd J_pose(n, 6), J_params(n, sensor.num_parameters());
      sensor.predict(params, fk.pose, reading, &J_pose, &J_params);
      // Differences are taken as the sensor's own reading error (tangent space for manifold
      // readings), the space its Jacobian rows live in.
      auto error_from_reading = [&](const VectorXd& other) -> VectorXd {
        VectorXd e(n);
        sensor.reading_error(other, reading, e, nullptr);
        return e;
      };
      auto at_params = [&](const VectorXd& p) {
        VectorXd r(n);
        sensor.predict(p, fk.pose, r, nullptr, nullptr);
        return error_from_reading(r);
      };
      auto at_pose = [&](const VectorXd& delta) {
        VectorXd r(n);
        sensor.predict(params, perturb(fk.pose, delta), r, nullptr, nullptr);
        return error_from_reading(r);
      };
      std::vector<std::string> names;
      for (const auto& p : sensor.parameters()) names.push_back(p.name);
      out.push_back(compare_jacobians("J_reading_params" + of, J_params,
                                      numerical_jacobian(at_params, params, 1e-6), 1e-6, names));
      out.push_back(compare_jacobians("J_reading_pose" + of, J_pose,
                                      numerical_jacobian(at_pose, VectorXd::Zero(6), 1e-6), 1e-6,
                                      {"dx", "dy", "dz", "wx", "wy", "wz"}));
    }
  });
  return out;
}

std::vector<ConformanceCheck> check_residual_jacobian(const ModelFactory& make) {
  // Through forward kinematics, the sensors and their reading errors, with the data measured
  // at the truth and the parameters at nominal.
  std::vector<ConformanceCheck> out;
  const std::string name = "Jacobian of the calibration residuals";
  guarded(out, name, [&] {
    const Scenario s = scenario_of(make, 5);
    const auto problem = s.make_problem();
    const VectorXd x = problem->initial_free_parameters();
    VectorXd r;
    MatrixXd J;
    std::string why;
    if (!problem->evaluate(x, &r, &J, &why)) throw std::runtime_error(why);
    std::string failure;
    auto residuals_at = [&](const VectorXd& p) {
      VectorXd values;
      if (!problem->evaluate(p, &values, nullptr, &why)) failure = why;
      return values;
    };
    const MatrixXd numeric = numerical_jacobian(residuals_at, x, 1e-6);
    if (!failure.empty()) throw std::runtime_error(failure);
    out.push_back(compare_jacobians(name, J, numeric, 1e-6, problem->parameter_names()));
  });
  return out;
}

std::vector<ConformanceCheck> check_inverse_kinematics(const ModelFactory& make) {
  std::vector<ConformanceCheck> out;
  const std::string name = "inverse kinematics round trip";
  guarded(out, name, [&] {
    const Scenario s = scenario_of(make, 6);
    const Mechanism& mechanism = s.model->mechanism();
    const VectorXd params = s.truth.head(mechanism.num_parameters());
    const auto fk_options = s.model->forward_kinematics_options();
    VectorXd q(mechanism.num_actuators());
    ConformanceCheck check{name, true, 0, 1e-8, ""};
    for (int j = 0; j < s.calibration.size(); ++j) {
      const auto fk = mechanism.forward_kinematics(
          params, s.calibration.actuators.row(j).transpose(), mechanism.home_pose(), fk_options);
      if (!fk.ok()) throw std::runtime_error("forward kinematics: " + fk.describe());
      const auto ik = mechanism.inverse_kinematics(params, fk.pose, q);
      if (!ik.ok()) {
        out.push_back(
            failed(name, "configuration " + std::to_string(j) + ": " + ik.describe(), 1e-8));
        return;
      }
      const auto back = mechanism.forward_kinematics(params, q, mechanism.home_pose(), fk_options);
      if (!back.ok()) throw std::runtime_error("forward kinematics: " + back.describe());
      const double d = pose_difference(fk.pose, back.pose).norm();
      if (!(d <= check.worst)) {
        check.worst = d;
        check.detail =
            "worst at configuration " + std::to_string(j) + " (|pose difference|, mm and rad)";
      }
    }
    check.passed = check.worst < check.tolerance;
    if (check.detail.empty()) check.detail = "every configuration returns exactly";
    out.push_back(check);
  });
  return out;
}

namespace {

std::vector<std::string> least_squares_variants(const SolverRegistry& solvers) {
  std::vector<std::string> names;
  for (const auto& info : solvers.list())
    if (info.kind == SolverKind::kLeastSquares)
      names.insert(names.end(), info.variants.begin(), info.variants.end());
  return names;
}

}  // namespace

std::vector<ConformanceCheck> check_recovery(const ModelFactory& make,
                                             const SolverRegistry& solvers) {
  std::vector<ConformanceCheck> out;
  for (const std::string& solver_name : least_squares_variants(solvers)) {
    const std::string name = "zero-noise recovery with " + solver_name;
    guarded(out, name, [&] {
      ConformanceCheck check{name, true, 0, 1e-6, ""};
      std::string not_converged;
      for (std::uint64_t seed : {1, 2}) {
        const Scenario s = scenario_of(make, seed);
        const auto solver = solvers.create(solver_name);
        const CalibrationRun run = run_calibration(s, *solver, SolverOptions{}, false);
        if (run.summary.termination != TerminationType::kConverged && not_converged.empty())
          not_converged =
              "seed " + std::to_string(seed) + ": did not converge (" + run.summary.message + ")";
        for (int i : s.free_indices) {
          const Parameter& p = s.model->parameters()[i];
          double d = run.estimate[i] - s.truth[i];
          if (p.unit == kRadian) d = wrap_angle(d);
          if (check.detail.empty() || !(std::abs(d) <= check.worst)) {
            check.worst = std::abs(d);
            check.detail = "worst " + p.name + " (" + p.unit + "), seed " + std::to_string(seed);
          }
        }
      }
      check.passed = not_converged.empty() && check.worst < check.tolerance;
      if (!not_converged.empty()) check.detail = not_converged + "; " + check.detail;
      out.push_back(check);
    });
  }
  return out;
}

std::vector<ConformanceCheck> check_model(const ModelFactory& make, const SolverRegistry& solvers) {
  std::vector<ConformanceCheck> out;
  const std::vector<ConformanceCheck> residual_jacobian = check_residual_jacobian(make);
  const bool jacobian_right = std::all_of(residual_jacobian.begin(), residual_jacobian.end(),
                                          [](const ConformanceCheck& c) { return c.passed; });
  // With a wrong residual Jacobian a backend's failure says nothing new, and running every
  // backend to its iteration limit takes minutes (under a sanitizer): each recovery is a
  // failure that names the reason instead.
  std::vector<ConformanceCheck> recovery;
  if (jacobian_right) {
    recovery = check_recovery(make, solvers);
  } else {
    for (const std::string& solver_name : least_squares_variants(solvers))
      recovery.push_back(failed("zero-noise recovery with " + solver_name,
                                "not run: the Jacobian of the calibration residuals is wrong "
                                "(above); fix it first",
                                1e-6));
  }
  for (auto part :
       {check_model_file(make), check_mechanism_jacobians(make), check_sensor_jacobians(make),
        residual_jacobian, check_inverse_kinematics(make), recovery})
    out.insert(out.end(), part.begin(), part.end());
  return out;
}

std::vector<ConformanceCheck> check_registry_coverage(const ModelRegistry& registry) {
  std::vector<ConformanceCheck> out;
  std::set<std::string> mechanisms, sensors;
  for (const auto& p : registry.presets()) {
    const std::string name = "preset " + p.name;
    guarded(out, name, [&] {
      const auto model = p.make();
      mechanisms.insert(model->mechanism().type());
      for (const auto& s : model->sensors()) sensors.insert(s->type());
      std::string why;
      if (model->parameters().num_free() == 0) why = "frees no parameter";
      if (p.description.empty()) why = "has no description (say what it is and cite its source)";
      out.push_back({name, why.empty(), 0, 0, why.empty() ? "frees parameters, described" : why});
    });
  }
  for (const auto& t : registry.mechanisms())
    out.push_back({"mechanism type " + t.type + " in a preset", mechanisms.count(t.type) > 0, 0, 0,
                   mechanisms.count(t.type) ? "" : "no preset uses it, so no check reaches it"});
  for (const auto& t : registry.sensors())
    out.push_back({"sensor type " + t.type + " in a preset", sensors.count(t.type) > 0, 0, 0,
                   sensors.count(t.type) ? "" : "no preset uses it, so no check reaches it"});
  return out;
}

}  // namespace kincal
