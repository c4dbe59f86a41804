#include "kincal/models/joint_compliance.hpp"

#include <cmath>
#include <stdexcept>

#include "kincal/framework/base/message_excerpt.hpp"

namespace kincal {

const char* to_string(GravityMasses masses) {
  return masses == GravityMasses::kGiven ? "given" : "fitted";
}

namespace {

// A torque in N m from kg * mm of moment arm and g.
constexpr double kNewtonMetresPerKgMm = kStandardGravity / 1000.0;

// Half-widths of the errors a simulation draws for the parameters (and multi-start's
// spread): a stiff industrial joint is 1e-6 to 1e-5 rad/Nm (a UR5's shoulder about 3e-6),
// so 2e-5 rad/Nm covers light arms; a moment of 2e-4 rad/m is 2e-5 rad/Nm times 10 kg.
constexpr double kComplianceHalfWidthRad = 2e-5;
constexpr double kComplianceHalfWidthMm = 2e-3;
constexpr double kMomentHalfWidthRad = 2e-3;
constexpr double kMomentHalfWidthMm = 0.2;
constexpr double kTiltHalfWidth = 0.01;

// A point given in `frame`, in the frame's parent.
Vector3d point_in(const Pose& frame, const Vector3d& point) {
  return frame.rotation * point + frame.translation;
}

}  // namespace

Vector3d tilted_gravity(const Vector3d& g0, double rx, double ry, Vector3d* d_rx, Vector3d* d_ry) {
  const double cx = std::cos(rx), sx = std::sin(rx), cy = std::cos(ry), sy = std::sin(ry);
  Matrix3d Rx, Ry;
  Rx << 1, 0, 0, 0, cx, -sx, 0, sx, cx;
  Ry << cy, 0, sy, 0, 1, 0, -sy, 0, cy;
  const Vector3d gx = Rx * g0;
  const Vector3d g = Ry * gx;
  if (d_rx) *d_rx = Ry * Vector3d::UnitX().cross(gx);
  if (d_ry) *d_ry = Vector3d::UnitY().cross(g);
  return g;
}

JointCompliance::JointCompliance(const ComplianceSpec& spec,
                                 const std::vector<std::string>& joint_names,
                                 const std::vector<bool>& revolute)
    : spec_(spec), joint_names_(joint_names), revolute_(revolute) {
  if (!spec_.enabled) return;
  const int n = static_cast<int>(joint_names.size());
  if (n > kMaxCompliantJoints)
    throw std::invalid_argument("joint compliance: at most " + std::to_string(kMaxCompliantJoints) +
                                " moving joints (this chain has " + std::to_string(n) + ")");
  const double norm = spec_.gravity.norm();
  if (!(norm > 1e-9) || !std::isfinite(norm))
    throw std::invalid_argument("joint compliance: the gravity direction is zero or not finite");
  spec_.gravity /= norm;
  if (spec_.masses == GravityMasses::kGiven && static_cast<int>(spec_.links.size()) != n)
    throw std::invalid_argument("joint compliance: " + std::to_string(spec_.links.size()) +
                                " link masses for " + std::to_string(n) + " moving joints");
  for (const PointMass& m : spec_.links)
    if (!(m.mass >= 0) || !std::isfinite(m.mass) || !m.centre.allFinite())
      throw std::invalid_argument("joint compliance: a link mass is negative or not finite");
  if (!(spec_.payload.mass >= 0) || !std::isfinite(spec_.payload.mass) ||
      !spec_.payload.centre.allFinite())
    throw std::invalid_argument("joint compliance: the payload mass is negative or not finite");
  if (spec_.payload_column && !(spec_.payload_max > 0 && std::isfinite(spec_.payload_max)))
    throw std::invalid_argument("joint compliance: the payload column's maximum must be > 0");

  parameters_.push_back({"gravity.rx", 0, "rad", false, kTiltHalfWidth});
  parameters_.push_back({"gravity.ry", 0, "rad", false, kTiltHalfWidth});
  has_compliances_ =
      spec_.masses == GravityMasses::kGiven || spec_.payload_column || spec_.payload.mass > 0;
  compliance_index_ = num_parameters();
  if (has_compliances_)
    for (int i = 0; i < n; ++i)
      parameters_.push_back({joint_names[i] + ".compliance", 0,
                             revolute[i] ? kRadianPerNewtonMetre : kMillimetrePerNewton, false,
                             revolute[i] ? kComplianceHalfWidthRad : kComplianceHalfWidthMm});
  moment_index_ = num_parameters();
  if (spec_.masses == GravityMasses::kFitted)
    for (int i = 0; i < n; ++i)
      for (int k = i + 1; k <= n; ++k) {
        moments_.emplace_back(i, k);
        parameters_.push_back(
            {joint_names[i] + ".moment." + (k < n ? joint_names[k] : std::string("tip")), 0,
             revolute[i] ? kRadianPerMetre : "mm", false,
             revolute[i] ? kMomentHalfWidthRad : kMomentHalfWidthMm});
      }
  for (const auto& [name, value] : spec_.values) {
    bool found = false;
    for (Parameter& p : parameters_)
      if (p.name == name) {
        if (!std::isfinite(value))
          throw std::invalid_argument("joint compliance: '" + message_excerpt(name) +
                                      "' is not finite");
        p.nominal = value;
        found = true;
      }
    if (!found)
      throw std::invalid_argument("joint compliance: no parameter '" + message_excerpt(name) +
                                  "' in this model (" + to_string(spec_.masses) + " masses)");
  }
}

void JointCompliance::scale_tolerances(const GravityChain& chain) {
  const int n = chain.joints;
  // The largest weight moment about each joint: masses times distances (not levers: gravity
  // and the joint's own angle may turn any distance into a lever).
  double moment = spec_.payload_column ? spec_.payload_max : spec_.payload.mass;
  double mass_beyond = moment;
  moment *= (point_in(chain.tip, spec_.payload.centre) - chain.origin[n - 1]).norm();
  for (int i = n - 1; i >= 0; --i) {
    if (i < n - 1 && i >= 0) moment += mass_beyond * (chain.origin[i + 1] - chain.origin[i]).norm();
    if (spec_.masses == GravityMasses::kGiven) {
      const PointMass& link = spec_.links[static_cast<std::size_t>(i)];
      moment += link.mass * (point_in(chain.link[i], link.centre) - chain.origin[i]).norm();
      mass_beyond += link.mass;
    }
    if (has_compliances_) {
      const double bound =
          chain.revolute[i] ? kNewtonMetresPerKgMm * moment : kStandardGravity * mass_beyond;
      if (bound > 0)
        parameters_[static_cast<std::size_t>(compliance_index_ + i)].error_half_width =
            (chain.revolute[i] ? 1e-3 : 1.0) / bound;
    }
  }
  for (std::size_t m = 0; m < moments_.size(); ++m) {
    const auto [i, k] = moments_[m];
    if (!chain.revolute[i]) continue;
    const Vector3d& point = k < n ? chain.origin[k] : chain.tip.translation;
    const double lever = (point - chain.origin[i]).norm() / 1000.0;
    if (lever > 0)
      parameters_[static_cast<std::size_t>(moment_index_) + m].error_half_width = 1e-3 / lever;
  }
}

void JointCompliance::add_to(std::vector<Parameter>& parameters, std::vector<Actuator>& actuators,
                             std::set<std::string>& names, const std::string& arm) const {
  for (const Parameter& p : parameters_) {
    if (!names.insert(p.name).second)
      throw std::invalid_argument(arm + ": parameter '" + p.name + "' is named twice");
    parameters.push_back(p);
  }
  if (spec_.payload_column) {
    if (!names.insert("payload").second)
      throw std::invalid_argument(arm + ": a joint named 'payload' and a payload column");
    actuators.push_back({"payload", kKilogram, 0.5 * spec_.payload_max, false});
  }
}

VectorXd JointCompliance::appended_to(const VectorXd& geometric) const {
  VectorXd out(geometric.size() + num_parameters());
  out.head(geometric.size()) = geometric;
  for (int k = 0; k < num_parameters(); ++k)
    out[geometric.size() + k] = parameters_[static_cast<std::size_t>(k)].nominal;
  return out;
}

std::vector<int> JointCompliance::indices(int first) const {
  std::vector<int> out;
  for (int k = 0; k < num_parameters(); ++k) out.push_back(first + k);
  return out;
}

ComplianceSpec JointCompliance::spec_with(const Eigen::Ref<const VectorXd>& values) const {
  ComplianceSpec out = spec_;
  out.values.clear();
  for (int p = 0; p < num_parameters(); ++p)
    if (values[p] != 0) out.values.emplace_back(parameters_[p].name, values[p]);
  return out;
}

void JointCompliance::deflections(const GravityChain& chain, const double* values, double payload,
                                  JointVector& delta, DeflectionJacobian* dDelta) const {
  const int n = chain.joints;
  delta.setZero(n);
  if (dDelta) dDelta->setZero(n, num_parameters());
  const double rx = values[0], ry = values[1];
  Vector3d g_rx, g_ry;
  const Vector3d g = tilted_gravity(spec_.gravity, rx, ry, &g_rx, &g_ry);
  if (has_compliances_) {
    // The torques are linear in g: tau_i = g . v_i; v_i carries the tilt derivatives.
    double mass = spec_.payload_column ? payload : spec_.payload.mass;
    Vector3d moment = mass * point_in(chain.tip, spec_.payload.centre);
    for (int i = n - 1; i >= 0; --i) {
      if (spec_.masses == GravityMasses::kGiven) {
        const PointMass& link = spec_.links[static_cast<std::size_t>(i)];
        mass += link.mass;
        moment += link.mass * point_in(chain.link[i], link.centre);
      }
      const Vector3d v = chain.revolute[i]
                             ? Vector3d(kNewtonMetresPerKgMm *
                                        chain.axis[i].cross(moment - mass * chain.origin[i]))
                             : Vector3d(kStandardGravity * mass * chain.axis[i]);
      const double tau = g.dot(v), c = values[compliance_index_ + i];
      delta[i] += c * tau;
      if (dDelta) {
        (*dDelta)(i, compliance_index_ + i) = tau;
        (*dDelta)(i, 0) += c * g_rx.dot(v);
        (*dDelta)(i, 1) += c * g_ry.dot(v);
      }
    }
  }
  for (std::size_t m = 0; m < moments_.size(); ++m) {
    const auto [i, k] = moments_[m];
    const Vector3d& point = k < n ? chain.origin[k] : chain.tip.translation;
    // The lever of a unit point mass at `point` about joint i, in m (revolute), or the axis
    // (prismatic: the weight's component along it).
    const Vector3d w = chain.revolute[i]
                           ? Vector3d(chain.axis[i].cross(point - chain.origin[i]) / 1000.0)
                           : chain.axis[i];
    const double mu = values[moment_index_ + static_cast<int>(m)];
    const double lever = g.dot(w);
    delta[i] += mu * lever;
    if (dDelta) {
      (*dDelta)(i, moment_index_ + static_cast<int>(m)) = lever;
      (*dDelta)(i, 0) += mu * g_rx.dot(w);
      (*dDelta)(i, 1) += mu * g_ry.dot(w);
    }
  }
}

}  // namespace kincal
