#pragma once
// A planar 3-RPR parallel robot: a platform moving in the base plane z = 0 (pose x, y and a
// rotation theta about z), held by three legs. Leg i is a prismatic actuator between revolute
// joints at base point b_i (base frame) and platform point p_i (platform frame), both in the
// plane; it is q_i + o_i long, with q_i the commanded actuator value and o_i the leg's zero
// offset.
//
// Constraints: g_i = |t + R p_i - b_i| - (q_i + o_i) = 0, three of them, in the local pose
// coordinates (dx, dy, dtheta) of ClosedChainMechanism<3>'s motion basis.
// Parameters, per leg i = 1..3: leg<i>.base.{x,y}, leg<i>.platform.{x,y}, leg<i>.offset (mm).

#include <array>

#include "kincal/framework/kinematics/closed_chain_mechanism.hpp"

namespace kincal {

class ModelRegistry;

/// A pose of the plane: position (x, y) in mm and rotation theta about z in rad.
struct PlanarPose {
  double x = 0, y = 0, theta = 0;
};
/// The spatial pose of a planar one: t = (x, y, 0), R = Rz(theta).
Pose to_pose(const PlanarPose& planar);
/// The planar pose of `pose`, when it is one: |t_z| and the tilt of its z axis within
/// `tolerance` (mm, rad). Returns false otherwise.
bool to_planar_pose(const Pose& pose, PlanarPose& planar, double tolerance = 1e-9);

struct Planar3RprGeometry {
  std::array<Eigen::Vector2d, 3> base_joints;
  std::array<Eigen::Vector2d, 3> platform_joints;
  std::array<double, 3> leg_offsets{};
  PlanarPose home;
};

class Planar3Rpr final : public ClosedChainMechanism<3> {
 public:
  static constexpr int kLegs = 3;
  static constexpr int kParametersPerLeg = 5;
  /// Simulation and design draw leg values within this of home by default (mm): small
  /// platforms make the 3-RPR's rotation sensitive, and this keeps the preset's prototype
  /// inside its stroke.
  static constexpr double kDefaultLegRange = 15.0;

  /// All parameters fixed; free them through the measurement model's parameter set.
  explicit Planar3Rpr(const Planar3RprGeometry& geometry);

  std::string type() const override { return "planar-3rpr"; }
  const std::vector<Actuator>& actuators() const override { return actuators_; }
  const std::vector<Parameter>& parameters() const override { return parameters_; }
  const Pose& home_pose() const override { return home_; }
  const Planar3RprGeometry& nominal_geometry() const { return geometry_; }

  /// Closed form. A pose off the plane, a leg of zero length or non-finite values are
  /// statuses with a reason.
  InverseKinematicsResult inverse_kinematics(const ParamsRef& params, const Pose& pose,
                                             Eigen::Ref<VectorXd> q) const override;
  void constraints(const ParamsRef& params, const ActuatorsRef& q, const Pose& pose,
                   ConstraintVector& g, ConstraintJacobian* J_g_pose) const override;
  void constraint_jacobian_params(const ParamsRef& params, const ActuatorsRef& q, const Pose& pose,
                                  Eigen::Ref<ParamsJacobian> J_g_params) const override;
  /// Leg i's constraint involves only leg i's five parameters: 3 x 5 entries, no product.
  void constraint_jacobian_params_left(
      const ParamsRef& params, const ActuatorsRef& q, const Pose& pose,
      const ConstraintVector& lambda,
      Eigen::Ref<Eigen::RowVectorXd, 0, Eigen::InnerStride<>> out) const override;
  /// Three finite values, each leg longer than zero.
  bool actuators_valid(const ParamsRef& params, const ActuatorsRef& q) const override;

  static int base_index(int leg) { return kParametersPerLeg * leg; }
  static int platform_index(int leg) { return kParametersPerLeg * leg + 2; }
  static int offset_index(int leg) { return kParametersPerLeg * leg + 4; }

  /// Columns: the SE(3) perturbations [dt; dw] of dx, dy and dtheta.
  static MotionBasis planar_motion_basis();

 private:
  Planar3RprGeometry geometry_;
  Pose home_;
  std::vector<Actuator> actuators_;
  std::vector<Parameter> parameters_;
};

/// Registers the type (model-file reader/writer) and its preset.
void register_planar_3rpr(ModelRegistry& registry);

}  // namespace kincal
