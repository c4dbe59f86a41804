#include "kincal/models/hexapod.hpp"

#include <cmath>

namespace kincal {

namespace {

const char* const kAxes[3] = {"x", "y", "z"};

}  // namespace

Hexapod::Hexapod(const HexapodGeometry& geometry) : geometry_(geometry) {
  for (int leg = 0; leg < kLegs; ++leg) {
    const std::string prefix = "leg" + std::to_string(leg + 1);
    actuators_.push_back({prefix, "mm", kDefaultLegRange});
    for (int a = 0; a < 3; ++a)
      parameters_.push_back(
          {prefix + ".base." + kAxes[a], geometry.base_joints[leg][a], "mm", false});
    for (int a = 0; a < 3; ++a)
      parameters_.push_back(
          {prefix + ".platform." + kAxes[a], geometry.platform_joints[leg][a], "mm", false});
    parameters_.push_back({prefix + ".offset", geometry.leg_offsets[leg], "mm", false});
  }
}

HexapodGeometry Hexapod::geometry_from(const ParamsRef& params) const {
  HexapodGeometry g = geometry_;
  for (int leg = 0; leg < kLegs; ++leg) {
    g.base_joints[leg] = params.segment<3>(base_index(leg));
    g.platform_joints[leg] = params.segment<3>(platform_index(leg));
    g.leg_offsets[leg] = params[offset_index(leg)];
  }
  return g;
}

InverseKinematicsResult Hexapod::inverse_kinematics(const ParamsRef& params, const Pose& pose,
                                                    Eigen::Ref<VectorXd> q) const {
  InverseKinematicsResult result;
  for (int leg = 0; leg < kLegs; ++leg) {
    const Vector3d b = params.segment<3>(base_index(leg));
    const Vector3d p = params.segment<3>(platform_index(leg));
    const double length = (pose.transform_point(p) - b).norm();
    q[leg] = length - params[offset_index(leg)];
    if (!std::isfinite(q[leg])) {
      result.status = InverseKinematicsStatus::kNonFinite;
      result.reason = "leg " + std::to_string(leg + 1) + " length is not finite";
      return result;
    }
    if (!(length > 0)) {
      result.status = InverseKinematicsStatus::kUnreachable;
      result.reason = "leg " + std::to_string(leg + 1) + " would have zero length";
      return result;
    }
  }
  return result;
}

bool Hexapod::actuators_valid(const ParamsRef& params, const ActuatorsRef& q) const {
  if (q.size() != kLegs || !q.allFinite()) return false;
  for (int leg = 0; leg < kLegs; ++leg)
    if (!(q[leg] + params[offset_index(leg)] > 0.0)) return false;
  return true;
}

namespace {

// Every leg at a pose: the rotated platform joint a = R p, the leg vector v = t + a - b and
// its length, in arrays leg by leg, so that the six square roots (and the divisions that
// follow them), whose latency is most of a constraint evaluation, are independent and run
// in pairs. The arithmetic is Eigen's for each leg, so the values are those of a per-leg loop.
struct Legs {
  double a[3][Hexapod::kLegs], v[3][Hexapod::kLegs], length[Hexapod::kLegs];

  Legs(const ParamsRef& params, const Pose& pose) {
    for (int leg = 0; leg < Hexapod::kLegs; ++leg) {
      const Vector3d rotated = pose.rotation * params.segment<3>(Hexapod::platform_index(leg));
      const Vector3d leg_vector =
          pose.translation + rotated - params.segment<3>(Hexapod::base_index(leg));
      for (int i = 0; i < 3; ++i) {
        a[i][leg] = rotated[i];
        v[i][leg] = leg_vector[i];
      }
    }
    for (int leg = 0; leg < Hexapod::kLegs; ++leg)
      length[leg] =
          std::sqrt(v[0][leg] * v[0][leg] + v[1][leg] * v[1][leg] + v[2][leg] * v[2][leg]);
  }

  /// Unit vector along the leg: the direction in which its length grows.
  Vector3d direction(int leg) const {
    return Vector3d(v[0][leg] / length[leg], v[1][leg] / length[leg], v[2][leg] / length[leg]);
  }
  Vector3d arm(int leg) const { return Vector3d(a[0][leg], a[1][leg], a[2][leg]); }
};

}  // namespace

void Hexapod::constraints(const ParamsRef& params, const ActuatorsRef& q, const Pose& pose,
                          Vector6d& g, Matrix6d* J_g_pose) const {
  const Legs legs(params, pose);
  for (int leg = 0; leg < kLegs; ++leg)
    g[leg] = legs.length[leg] - (q[leg] + params[offset_index(leg)]);
  if (!J_g_pose) return;
  // d|v| = n . dv with dv = dt + dw x a  =>  row = [n^T, (a x n)^T].
  for (int leg = 0; leg < kLegs; ++leg) {
    const Vector3d n = legs.direction(leg);
    J_g_pose->row(leg).head<3>() = n.transpose();
    J_g_pose->row(leg).tail<3>() = legs.arm(leg).cross(n).transpose();
  }
}

void Hexapod::constraint_jacobian_params(const ParamsRef& params, const ActuatorsRef&,
                                         const Pose& pose, Eigen::Ref<Matrix6Xd> J_g_params) const {
  J_g_params.setZero();
  const Legs legs(params, pose);
  for (int leg = 0; leg < kLegs; ++leg) {
    const Vector3d n = legs.direction(leg);
    J_g_params.block<1, 3>(leg, base_index(leg)) = -n.transpose();
    J_g_params.block<1, 3>(leg, platform_index(leg)) = n.transpose() * pose.rotation;
    J_g_params(leg, offset_index(leg)) = -1.0;
  }
}

void Hexapod::constraint_jacobian_params_left(
    const ParamsRef& params, const ActuatorsRef&, const Pose& pose, const Vector6d& lambda,
    Eigen::Ref<Eigen::RowVectorXd, 0, Eigen::InnerStride<>> out) const {
  // Every parameter belongs to exactly one leg, so every entry of `out` is written.
  const Legs legs(params, pose);
  for (int leg = 0; leg < kLegs; ++leg) {
    const Vector3d weighted = lambda[leg] * legs.direction(leg);
    out.segment<3>(base_index(leg)) = -weighted.transpose();
    out.segment<3>(platform_index(leg)) = weighted.transpose() * pose.rotation;
    out[offset_index(leg)] = -lambda[leg];
  }
}

}  // namespace kincal
