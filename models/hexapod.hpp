#pragma once
// A general 6-UPS hexapod: six legs from base joints b_i (base frame) to platform joints
// p_i (platform frame). Leg i is q_i + o_i long, with q_i the commanded actuator value and
// o_i the leg's zero offset (0 for absolute encoders).
//
// Constraints: g_i = |t + R p_i - b_i| - (q_i + o_i) = 0.
// Parameters, per leg i = 1..6: leg<i>.base.{x,y,z}, leg<i>.platform.{x,y,z}, leg<i>.offset.

#include <array>

#include "kincal/framework/kinematics/closed_chain_mechanism.hpp"

namespace kincal {

class ModelRegistry;

struct HexapodGeometry {
  std::array<Vector3d, 6> base_joints;
  std::array<Vector3d, 6> platform_joints;
  std::array<double, 6> leg_offsets{};
  Pose home;
};

class Hexapod final : public ClosedChainMechanism<6> {
 public:
  static constexpr int kLegs = 6;
  static constexpr int kParametersPerLeg = 7;
  /// Simulation and design draw leg lengths within this of home by default (the paper's
  /// +-20 mm, section 4).
  static constexpr double kDefaultLegRange = 20.0;

  /// All parameters fixed; free them through the measurement model's parameter set.
  explicit Hexapod(const HexapodGeometry& geometry);

  std::string type() const override { return "hexapod-6ups"; }
  const std::vector<Actuator>& actuators() const override { return actuators_; }
  const std::vector<Parameter>& parameters() const override { return parameters_; }
  const Pose& home_pose() const override { return geometry_.home; }
  const HexapodGeometry& nominal_geometry() const { return geometry_; }

  /// The geometry stored in a parameter vector (home pose from the nominal geometry).
  HexapodGeometry geometry_from(const ParamsRef& params) const;

  InverseKinematicsResult inverse_kinematics(const ParamsRef& params, const Pose& pose,
                                             Eigen::Ref<VectorXd> q) const override;
  void constraints(const ParamsRef& params, const ActuatorsRef& q, const Pose& pose, Vector6d& g,
                   Matrix6d* J_g_pose) const override;
  void constraint_jacobian_params(const ParamsRef& params, const ActuatorsRef& q, const Pose& pose,
                                  Eigen::Ref<Matrix6Xd> J_g_params) const override;
  /// Leg i's constraint involves only leg i's seven parameters: 6 x 7 entries, no product.
  void constraint_jacobian_params_left(
      const ParamsRef& params, const ActuatorsRef& q, const Pose& pose, const Vector6d& lambda,
      Eigen::Ref<Eigen::RowVectorXd, 0, Eigen::InnerStride<>> out) const override;
  bool actuators_valid(const ParamsRef& params, const ActuatorsRef& q) const override;

  static int base_index(int leg) { return kParametersPerLeg * leg; }
  static int platform_index(int leg) { return kParametersPerLeg * leg + 3; }
  static int offset_index(int leg) { return kParametersPerLeg * leg + 6; }

 private:
  HexapodGeometry geometry_;
  std::vector<Actuator> actuators_;
  std::vector<Parameter> parameters_;
};

/// Registers the type (model-file reader/writer) and its presets.
void register_hexapod(ModelRegistry& registry);

}  // namespace kincal
