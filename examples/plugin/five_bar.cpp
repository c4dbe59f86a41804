#include "five_bar.hpp"

#include <cmath>
#include <kincal/framework/closed_chain_mechanism_impl.hpp>
#include <kincal/framework/units.hpp>

// Forward kinematics and the pose Jacobian for two constraints: kincal compiles sizes 3
// and 6 into the library, any other is instantiated by the mechanism that needs it.
template class kincal::ClosedChainMechanism<2>;

namespace five_bar_plugin {

using namespace kincal;

namespace {

// Columns: the SE(3) perturbations [dt; dw] of the local pose coordinates dx and dy.
FiveBar::MotionBasis planar_translation_basis() {
  FiveBar::MotionBasis basis = FiveBar::MotionBasis::Zero();
  basis(0, 0) = 1;
  basis(1, 1) = 1;
  return basis;
}

struct ArmState {
  double theta;               // joint angle, q + offset
  Eigen::Vector2d direction;  // (cos theta, sin theta)
  Eigen::Vector2d to_end;     // P - E
  double distance;            // |P - E|
};

ArmState arm_state(const ParamsRef& params, const ActuatorsRef& q, const Pose& pose, int arm) {
  ArmState s;
  s.theta = q[arm] + params[FiveBar::offset_index(arm)];
  s.direction = Eigen::Vector2d(std::cos(s.theta), std::sin(s.theta));
  const Eigen::Vector2d elbow = params.segment<2>(FiveBar::base_index(arm)) +
                                params[FiveBar::proximal_index(arm)] * s.direction;
  s.to_end = pose.translation.head<2>() - elbow;
  s.distance = s.to_end.norm();
  return s;
}

// The Jacobians, one function each, written by hand (each is held to finite differences by
// `kincal check`). d g_i / d(dx, dy): the unit vector from the elbow to the end effector.
Eigen::RowVector2d constraint_row_pose(const ArmState& s) {
  return (s.to_end / s.distance).transpose();
}

// d g_i / d(arm i's parameters): base x, base y, proximal, distal, offset.
Eigen::Matrix<double, 1, 5> constraint_row_params(const ArmState& s, double proximal) {
  const Eigen::Vector2d n = s.to_end / s.distance;
  const Eigen::Vector2d d_elbow_d_theta =
      proximal * Eigen::Vector2d(-s.direction.y(), s.direction.x());
  Eigen::Matrix<double, 1, 5> row;
  row << -n.x(), -n.y(), -n.dot(s.direction), -1.0, -n.dot(d_elbow_d_theta);
#ifdef FIVE_BAR_FLIP_A_SIGN  // kincal's own test builds this to see `kincal check` fail
  row(4) = -row(4);
#endif
  return row;
}

}  // namespace

FiveBar::FiveBar(const FiveBarGeometry& geometry)
    : ClosedChainMechanism<2>(planar_translation_basis()), geometry_(geometry) {
  home_.translation = Vector3d(geometry.home.x(), geometry.home.y(), 0.0);
  for (int arm = 0; arm < kArms; ++arm) {
    const std::string prefix = "arm" + std::to_string(arm + 1);
    const FiveBarArm& a = geometry.arms[arm];
    actuators_.push_back({"joint" + std::to_string(arm + 1), kRadian, kDefaultJointRange});
    parameters_.push_back({prefix + ".base.x", a.base.x(), kMillimetre, false});
    parameters_.push_back({prefix + ".base.y", a.base.y(), kMillimetre, false});
    parameters_.push_back({prefix + ".proximal", a.proximal, kMillimetre, false});
    parameters_.push_back({prefix + ".distal", a.distal, kMillimetre, false});
    parameters_.push_back({prefix + ".offset", a.offset, kRadian, false});
  }
}

InverseKinematicsResult FiveBar::inverse_kinematics(const ParamsRef& params, const Pose& pose,
                                                    Eigen::Ref<VectorXd> q) const {
  InverseKinematicsResult result;
  if (!pose.translation.allFinite() || !pose.rotation.allFinite() || !params.allFinite()) {
    result.status = InverseKinematicsStatus::kNonFinite;
    result.reason = "the pose or the parameters are not finite";
    return result;
  }
  // The end effector moves in the plane z = 0 and does not turn.
  if (std::abs(pose.translation.z()) > 1e-9 ||
      (pose.rotation - Matrix3d::Identity()).cwiseAbs().maxCoeff() > 1e-9) {
    result.status = InverseKinematicsStatus::kUnreachable;
    result.reason = "a five-bar's end effector moves in the plane z = 0 without turning";
    return result;
  }
  for (int arm = 0; arm < kArms; ++arm) {
    const Eigen::Vector2d w = pose.translation.head<2>() - params.segment<2>(base_index(arm));
    const double reach = w.norm(), l = params[proximal_index(arm)], d = params[distal_index(arm)];
    // The elbow is on both circles: |E - A| = l, |P - E| = d (law of cosines at A).
    const double cos_beta = (l * l + reach * reach - d * d) / (2 * l * reach);
    if (!(reach > 0) || !(std::abs(cos_beta) <= 1)) {
      result.status = InverseKinematicsStatus::kUnreachable;
      result.reason = "arm " + std::to_string(arm + 1) + " cannot reach the point";
      return result;
    }
    const double theta = std::atan2(w.y(), w.x()) + geometry_.arms[arm].elbow * std::acos(cos_beta);
    q[arm] = wrap_angle(theta - params[offset_index(arm)]);
  }
  return result;
}

void FiveBar::constraints(const ParamsRef& params, const ActuatorsRef& q, const Pose& pose,
                          ConstraintVector& g, ConstraintJacobian* J_g_pose) const {
  for (int arm = 0; arm < kArms; ++arm) {
    const ArmState s = arm_state(params, q, pose, arm);
    g[arm] = s.distance - params[distal_index(arm)];
    if (J_g_pose) J_g_pose->row(arm) = constraint_row_pose(s);
  }
}

void FiveBar::constraint_jacobian_params(const ParamsRef& params, const ActuatorsRef& q,
                                         const Pose& pose,
                                         Eigen::Ref<ParamsJacobian> J_g_params) const {
  J_g_params.setZero();
  for (int arm = 0; arm < kArms; ++arm)
    J_g_params.block<1, kParametersPerArm>(arm, base_index(arm)) =
        constraint_row_params(arm_state(params, q, pose, arm), params[proximal_index(arm)]);
}

}  // namespace five_bar_plugin
