#include "two_link_arm.hpp"

#include <cmath>

namespace example {

using namespace kincal;

namespace {

enum Index { kLink1, kLink2, kOffset1, kOffset2 };

// Elbow and tip of the arm for joint angles q with parameters p.
void tip(const ParamsRef& p, double q1, double q2, Vector3d& elbow, Vector3d& end, double& angle) {
  const double a1 = q1 + p[kOffset1];
  angle = a1 + q2 + p[kOffset2];
  elbow = Vector3d(p[kLink1] * std::cos(a1), p[kLink1] * std::sin(a1), 0);
  end = elbow + Vector3d(p[kLink2] * std::cos(angle), p[kLink2] * std::sin(angle), 0);
}

}  // namespace

TwoLinkArm::TwoLinkArm(double link1, double link2) {
  // Joint ranges for simulation and design: +-0.5 rad about home keeps the elbow bent.
  actuators_ = {{"joint1", kRadian, 0.5}, {"joint2", kRadian, 0.5}};
  parameters_ = {{"link1.length", link1, kMillimetre},
                 {"link2.length", link2, kMillimetre},
                 {"joint1.offset", 0.0, kRadian},
                 {"joint2.offset", 0.0, kRadian}};
  VectorXd nominal(4);
  nominal << link1, link2, 0, 0;
  const Eigen::Vector2d q(kHome[0], kHome[1]);
  home_ = forward_kinematics(nominal, q, Pose{}).pose;
}

InverseKinematicsResult TwoLinkArm::home_actuators(const ParamsRef&, Eigen::Ref<VectorXd> q) const {
  q << kHome[0], kHome[1];
  return {};
}

ForwardKinematicsResult TwoLinkArm::forward_kinematics(const ParamsRef& params,
                                                       const ActuatorsRef& q, const Pose&,
                                                       const ForwardKinematicsOptions&) const {
  ForwardKinematicsResult result;
  if (!q.allFinite() || !params.allFinite()) {
    result.status = ForwardKinematicsStatus::kNonFinite;
    return result;
  }
  Vector3d elbow, end;
  double angle;
  tip(params, q[0], q[1], elbow, end, angle);
  result.pose.translation = end;
  result.pose.rotation = Eigen::AngleAxisd(angle, Vector3d::UnitZ()).toRotationMatrix();
  return result;
}

void TwoLinkArm::pose_jacobian_params(const ParamsRef& params, const ActuatorsRef& q, const Pose&,
                                      Eigen::Ref<Matrix6Xd> J) const {
  // Each parameter moves the tip as an elementary motion: a link length slides it along the
  // link, an offset turns everything beyond its joint about z (perturbation [dt; dw]).
  Vector3d elbow, end;
  double angle;
  tip(params, q[0], q[1], elbow, end, angle);
  const Vector3d z = Vector3d::UnitZ();
  J.setZero();
  J.col(kLink1).head<3>() = elbow.normalized();
  J.col(kLink2).head<3>() = (end - elbow).normalized();
  J.col(kOffset1).head<3>() = z.cross(end);
  J.col(kOffset1).tail<3>() = z;
  J.col(kOffset2).head<3>() = z.cross(end - elbow);
  J.col(kOffset2).tail<3>() = z;
}

InverseKinematicsResult TwoLinkArm::inverse_kinematics(const ParamsRef& p, const Pose& pose,
                                                       Eigen::Ref<VectorXd> q) const {
  InverseKinematicsResult result;
  const Vector3d& t = pose.translation;
  if (!t.allFinite() || !pose.rotation.allFinite()) {
    result.status = InverseKinematicsStatus::kNonFinite;
    return result;
  }
  // Two joints reach a point of the plane; the orientation then follows and must match.
  const double l1 = p[kLink1], l2 = p[kLink2], r2 = t.head<2>().squaredNorm();
  const double c2 = (r2 - l1 * l1 - l2 * l2) / (2 * l1 * l2);
  if (std::abs(t.z()) > 1e-9 || !(std::abs(c2) <= 1)) {
    result.status = InverseKinematicsStatus::kUnreachable;
    result.reason = "the point is outside the arm's annulus in the z = 0 plane";
    return result;
  }
  const double a2 = std::acos(c2);  // elbow on the side of home (positive joint 2)
  const double a1 = std::atan2(t.y(), t.x()) - std::atan2(l2 * std::sin(a2), l1 + l2 * c2);
  q << a1 - p[kOffset1], a2 - p[kOffset2];
  const double angle = std::atan2(pose.rotation(1, 0), pose.rotation(0, 0));
  if (std::abs(std::remainder(angle - (a1 + a2), 2 * M_PI)) > 1e-9 ||
      std::abs(pose.rotation(2, 2) - 1) > 1e-9) {
    result.status = InverseKinematicsStatus::kUnreachable;
    result.reason = "a two-link arm cannot take that orientation at that point";
  }
  return result;
}

}  // namespace example
