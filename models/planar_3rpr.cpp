#include "kincal/models/planar_3rpr.hpp"

#include <cmath>
#include <cstdio>

namespace kincal {

Pose to_pose(const PlanarPose& planar) {
  Pose pose;
  pose.translation = Vector3d(planar.x, planar.y, 0.0);
  pose.rotation = Eigen::AngleAxisd(planar.theta, Vector3d::UnitZ()).toRotationMatrix();
  return pose;
}

bool to_planar_pose(const Pose& pose, PlanarPose& planar, double tolerance) {
  const Matrix3d& R = pose.rotation;
  // sin of the angle between the platform's z axis and the base's.
  const double tilt = std::hypot(R(0, 2), R(1, 2));
  if (!(std::abs(pose.translation.z()) <= tolerance) || !(tilt <= tolerance) || !(R(2, 2) > 0))
    return false;
  planar.x = pose.translation.x();
  planar.y = pose.translation.y();
  planar.theta = std::atan2(R(1, 0), R(0, 0));
  return true;
}

Planar3Rpr::MotionBasis Planar3Rpr::planar_motion_basis() {
  MotionBasis basis = MotionBasis::Zero();
  basis(0, 0) = 1;  // dx: translation along base x
  basis(1, 1) = 1;  // dy: translation along base y
  basis(5, 2) = 1;  // dtheta: rotation about base z
  return basis;
}

Planar3Rpr::Planar3Rpr(const Planar3RprGeometry& geometry)
    : ClosedChainMechanism<3>(planar_motion_basis()),
      geometry_(geometry),
      home_(to_pose(geometry.home)) {
  const char* const axes[2] = {"x", "y"};
  for (int leg = 0; leg < kLegs; ++leg) {
    const std::string prefix = "leg" + std::to_string(leg + 1);
    actuators_.push_back({prefix, "mm", kDefaultLegRange});
    for (int a = 0; a < 2; ++a)
      parameters_.push_back(
          {prefix + ".base." + axes[a], geometry.base_joints[leg][a], "mm", false});
    for (int a = 0; a < 2; ++a)
      parameters_.push_back(
          {prefix + ".platform." + axes[a], geometry.platform_joints[leg][a], "mm", false});
    parameters_.push_back({prefix + ".offset", geometry.leg_offsets[leg], "mm", false});
  }
}

namespace {

// Leg `leg` at `pose`: the vector from its base joint to its platform joint, and the
// platform joint's offset from the platform origin in base axes (a = R p).
struct LegVectors {
  Vector3d leg;
  Vector3d arm;
};

LegVectors leg_vectors(const ParamsRef& params, const Pose& pose, int leg) {
  LegVectors out;
  out.arm.noalias() =
      pose.rotation.leftCols<2>() * params.segment<2>(Planar3Rpr::platform_index(leg));
  out.leg = pose.translation + out.arm;
  out.leg.head<2>() -= params.segment<2>(Planar3Rpr::base_index(leg));
  return out;
}

}  // namespace

InverseKinematicsResult Planar3Rpr::inverse_kinematics(const ParamsRef& params, const Pose& pose,
                                                       Eigen::Ref<VectorXd> q) const {
  InverseKinematicsResult result;
  if (!pose.translation.allFinite() || !pose.rotation.allFinite() || !params.allFinite()) {
    result.status = InverseKinematicsStatus::kNonFinite;
    result.reason = "the pose or the parameters are not finite";
    return result;
  }
  PlanarPose planar;
  if (!to_planar_pose(pose, planar)) {
    char buf[160];
    std::snprintf(buf, sizeof buf,
                  "the platform moves in the plane z = 0 about the z axis; this pose is %.3g mm "
                  "off the plane and tilted by %.3g rad",
                  pose.translation.z(),
                  std::asin(std::min(1.0, std::hypot(pose.rotation(0, 2), pose.rotation(1, 2)))));
    result.status = InverseKinematicsStatus::kUnreachable;
    result.reason = buf;
    return result;
  }
  for (int leg = 0; leg < kLegs; ++leg) {
    const double length = leg_vectors(params, pose, leg).leg.norm();
    if (!(length > 0)) {
      result.status = InverseKinematicsStatus::kUnreachable;
      result.reason = "leg " + std::to_string(leg + 1) + " would have zero length";
      return result;
    }
    q[leg] = length - params[offset_index(leg)];
  }
  return result;
}

bool Planar3Rpr::actuators_valid(const ParamsRef& params, const ActuatorsRef& q) const {
  if (q.size() != kLegs || !q.allFinite()) return false;
  for (int leg = 0; leg < kLegs; ++leg)
    if (!(q[leg] + params[offset_index(leg)] > 0.0)) return false;
  return true;
}

void Planar3Rpr::constraints(const ParamsRef& params, const ActuatorsRef& q, const Pose& pose,
                             ConstraintVector& g, ConstraintJacobian* J_g_pose) const {
  for (int leg = 0; leg < kLegs; ++leg) {
    const LegVectors v = leg_vectors(params, pose, leg);
    const double length = v.leg.norm();
    g[leg] = length - (q[leg] + params[offset_index(leg)]);
    if (J_g_pose) {
      // d|v| = n . (dt + dw x a) with dt = (dx, dy, 0), dw = (0, 0, dtheta):
      // row = [n_x, n_y, (a x n)_z].
      const Vector3d n = v.leg / length;
      (*J_g_pose)(leg, 0) = n.x();
      (*J_g_pose)(leg, 1) = n.y();
      (*J_g_pose)(leg, 2) = v.arm.x() * n.y() - v.arm.y() * n.x();
    }
  }
}

void Planar3Rpr::constraint_jacobian_params(const ParamsRef& params, const ActuatorsRef&,
                                            const Pose& pose,
                                            Eigen::Ref<ParamsJacobian> J_g_params) const {
  J_g_params.setZero();
  for (int leg = 0; leg < kLegs; ++leg) {
    const Vector3d n = leg_vectors(params, pose, leg).leg.normalized();
    J_g_params.block<1, 2>(leg, base_index(leg)) = -n.head<2>().transpose();
    J_g_params.block<1, 2>(leg, platform_index(leg)) = n.transpose() * pose.rotation.leftCols<2>();
    J_g_params(leg, offset_index(leg)) = -1.0;
  }
}

void Planar3Rpr::constraint_jacobian_params_left(
    const ParamsRef& params, const ActuatorsRef&, const Pose& pose, const ConstraintVector& lambda,
    Eigen::Ref<Eigen::RowVectorXd, 0, Eigen::InnerStride<>> out) const {
  // Every parameter belongs to exactly one leg, so every entry of `out` is written.
  for (int leg = 0; leg < kLegs; ++leg) {
    const Vector3d weighted = lambda[leg] * leg_vectors(params, pose, leg).leg.normalized();
    out.segment<2>(base_index(leg)) = -weighted.head<2>().transpose();
    out.segment<2>(platform_index(leg)) = weighted.transpose() * pose.rotation.leftCols<2>();
    out[offset_index(leg)] = -lambda[leg];
  }
}

}  // namespace kincal
