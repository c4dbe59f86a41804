#include "five_bar.hpp"

#include <cmath>
#include <kincal/framework/kinematics/closed_chain_mechanism_impl.hpp>
#include <kincal/framework/kinematics/units.hpp>

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

}  // namespace

FiveBar::FiveBar(const FiveBarGeometry& geometry)
    : AutoDiffClosedChain<FiveBar, 2>(planar_translation_basis()), geometry_(geometry) {
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

#ifdef FIVE_BAR_FLIP_A_SIGN
// The automatic d g_i / d arm<i>.offset with its sign flipped: `kincal check` must name it.
void FiveBar::constraint_jacobian_params(const ParamsRef& params, const ActuatorsRef& q,
                                         const Pose& pose,
                                         Eigen::Ref<ParamsJacobian> J_g_params) const {
  AutoDiffClosedChain<FiveBar, 2>::constraint_jacobian_params(params, q, pose, J_g_params);
  for (int arm = 0; arm < kArms; ++arm)
    J_g_params(arm, offset_index(arm)) = -J_g_params(arm, offset_index(arm));
}
#endif

}  // namespace five_bar_plugin
