#pragma once
// A planar five-bar linkage (5R), a closed chain kincal does not ship: two actuated revolute
// joints at base points A1, A2 turn proximal links of lengths l1, l2; distal links of
// lengths d1, d2 join their ends (the elbows E1, E2) at the end effector P, which moves in
// the plane z = 0 without turning.
//
//   theta_i = q_i + o_i                 (o_i: the joint's zero offset)
//   E_i = A_i + l_i (cos theta_i, sin theta_i)
//   g_i = |P - E_i| - d_i = 0           (two constraints)
//
// As a ClosedChainMechanism<2>: the pose has two local coordinates, dx and dy (the motion
// basis), every Jacobian with respect to the pose is taken in them, and kincal's Newton
// solves forward kinematics from the two constraints. The constraints are written once, as
// a function template (autodiff_constraints): AutoDiffClosedChain derives both constraint
// Jacobians from it by automatic differentiation (kincal/framework/kinematics/autodiff.hpp).
// Inverse kinematics is closed form, on the elbow side each arm has at home (its "elbow" sign), and
// home_actuators is inverse kinematics of the home pose (Mechanism's default). Parameters, per arm
// i = 1, 2: arm<i>.base.{x,y}, arm<i>.proximal, arm<i>.distal (mm), arm<i>.offset (rad).

#include <array>
#include <kincal/framework/kinematics/autodiff.hpp>
#include <kincal/framework/kinematics/closed_chain_mechanism.hpp>

namespace five_bar_plugin {

struct FiveBarArm {
  Eigen::Vector2d base = Eigen::Vector2d::Zero();
  double proximal = 0, distal = 0, offset = 0;
  /// +1: the elbow lies to the left of the line from the base to the end effector, -1: right.
  int elbow = 1;
};

struct FiveBarGeometry {
  std::array<FiveBarArm, 2> arms;
  Eigen::Vector2d home = Eigen::Vector2d::Zero();  ///< the end effector at home (mm)
};

class FiveBar final : public kincal::AutoDiffClosedChain<FiveBar, 2> {
 public:
  static constexpr int kArms = 2;
  static constexpr int kParametersPerArm = 5;
  static constexpr double kDefaultJointRange = 0.25;  // rad about home

  explicit FiveBar(const FiveBarGeometry& geometry);

  std::string type() const override { return "five-bar"; }
  const std::vector<kincal::Actuator>& actuators() const override { return actuators_; }
  const std::vector<kincal::Parameter>& parameters() const override { return parameters_; }
  const kincal::Pose& home_pose() const override { return home_; }
  const FiveBarGeometry& nominal_geometry() const { return geometry_; }

  kincal::InverseKinematicsResult inverse_kinematics(const kincal::ParamsRef& params,
                                                     const kincal::Pose& pose,
                                                     Eigen::Ref<kincal::VectorXd> q) const override;
  /// g_i = |P - E_i| - d_i for both arms, for any scalar T (double, or the dual numbers
  /// AutoDiffClosedChain evaluates it on to get d g / d pose and d g / d params).
  template <class T>
  void autodiff_constraints(const T* params, const kincal::ActuatorsRef& q,
                            const kincal::PoseT<T>& pose, T* g) const {
    using std::cos;
    using std::sin;
    using std::sqrt;
    for (int arm = 0; arm < kArms; ++arm) {
      const T theta = params[offset_index(arm)] + q[arm];
      const T to_end_x = pose.translation[0] -
                         (params[base_index(arm)] + params[proximal_index(arm)] * cos(theta));
      const T to_end_y = pose.translation[1] -
                         (params[base_index(arm) + 1] + params[proximal_index(arm)] * sin(theta));
      g[arm] = sqrt(to_end_x * to_end_x + to_end_y * to_end_y) - params[distal_index(arm)];
    }
  }

#ifdef FIVE_BAR_FLIP_A_SIGN  // kincal's own test builds this to see `kincal check` fail
  void constraint_jacobian_params(const kincal::ParamsRef& params, const kincal::ActuatorsRef& q,
                                  const kincal::Pose& pose,
                                  Eigen::Ref<ParamsJacobian> J_g_params) const override;
#endif

  static int base_index(int arm) { return kParametersPerArm * arm; }
  static int proximal_index(int arm) { return kParametersPerArm * arm + 2; }
  static int distal_index(int arm) { return kParametersPerArm * arm + 3; }
  static int offset_index(int arm) { return kParametersPerArm * arm + 4; }

 private:
  FiveBarGeometry geometry_;
  kincal::Pose home_;
  std::vector<kincal::Actuator> actuators_;
  std::vector<kincal::Parameter> parameters_;
};

}  // namespace five_bar_plugin
