#pragma once
// Joint compliance inside a serial chain's walk (models/joint_compliance.hpp): what an arm
// with compliance (the urdf-arm, the serial-arm) does around serial_chain::walk, written once
// for any Links policy. The gravity torques are taken on the arm's fixed gravity geometry
// (`gravity_params`: its nominal parameters with the base frame at identity, so that the
// chain is in the base's coordinates), the deflected joint values go through the walk, and a
// compliance parameter's column is J_pose_q at the deflected joints times the deflection's
// derivative.

#include "kincal/models/joint_compliance.hpp"
#include "kincal/models/serial_chain.hpp"

namespace kincal::serial_chain {

/// Records the chain as gravity sees it: joints' axes and points, links' frames, the tip.
class GravityRecord : public PoseOnly {
 public:
  explicit GravityRecord(GravityChain& chain) : chain_(chain) {}
  void joint(int i, bool revolute, const Vector3d& axis, const Vector3d& origin) {
    chain_.revolute[i] = revolute;
    chain_.axis[i] = axis;
    chain_.origin[i] = origin;
  }
  void link(int i, const Pose& frame) { chain_.link[i] = frame; }
  void finish(const Pose& tip, const Pose&) { chain_.tip = tip; }

 private:
  GravityChain& chain_;
};

/// J_pose_params of the walk's own parameters and J_pose_q of the joints in one walk.
class ParameterAndJointColumns : public ParameterColumns {
 public:
  using JointColumnsMatrix = Eigen::Matrix<double, 6, Eigen::Dynamic, 0, 6, kMaxCompliantJoints>;
  ParameterAndJointColumns(Eigen::Ref<Matrix6Xd>& J, JointColumnsMatrix& Jq)
      : ParameterColumns(J), Jq_(Jq) {}
  void joint(int i, bool revolute, const Vector3d& axis, const Vector3d& origin) {
    if (revolute)
      rotation_column(Jq_.col(i), axis, origin);
    else
      translation_column(Jq_.col(i), axis);
  }
  void finish(const Pose& tip, const Pose& end) {
    ParameterColumns::finish(tip, end);
    for (Eigen::Index c = 0; c < Jq_.cols(); ++c)
      Jq_.col(c).head<3>() += Jq_.col(c).tail<3>().cross(end.translation);
  }

 private:
  JointColumnsMatrix& Jq_;
};

/// Where an arm keeps its compliance: the model, its first parameter (after the tool frame),
/// whether the payload is the actuator after the joints, the gravity geometry.
struct ComplianceLayout {
  const JointCompliance* compliance = nullptr;
  int first_parameter = 0;
  bool payload_actuator = false;
  const VectorXd* gravity_params = nullptr;
  bool enabled() const { return compliance && compliance->enabled(); }
};

/// The chain at q on the gravity geometry.
template <class Links>
void gravity_chain(const Links& links, const ComplianceLayout& c, const ActuatorsRef& q,
                   GravityChain& chain) {
  chain.joints = links.size();
  walk(links, *c.gravity_params, q, GravityRecord(chain));
}

/// The joints after their deflection under gravity (`deflection`: its derivatives).
template <class Links>
void deflect(const Links& links, const ComplianceLayout& c, const ParamsRef& params,
             const ActuatorsRef& q, JointVector& joints, DeflectionJacobian* deflection) {
  const int n = links.size();
  joints = q.head(n);  // n <= kMaxCompliantJoints: JointCompliance's constructor checked
  GravityChain chain;
  gravity_chain(links, c, q, chain);
  JointVector delta;
  c.compliance->deflections(chain, params.data() + c.first_parameter,
                            c.payload_actuator ? q[n] : 0.0, delta, deflection);
  joints += delta;
}

/// walk at the deflected joints (at q without compliance).
template <class Links, class Record>
Pose walk_deflected(const Links& links, const ComplianceLayout& c, const ParamsRef& params,
                    const ActuatorsRef& q, Record&& record) {
  if (!c.enabled()) return walk(links, params, q, record);
  JointVector joints;
  deflect(links, c, params, q, joints, nullptr);
  return walk(links, params, joints, record);
}

/// J_pose_params with the compliance parameters' columns.
template <class Links>
void compliant_parameter_columns(const Links& links, const ComplianceLayout& c,
                                 const ParamsRef& params, const ActuatorsRef& q,
                                 Eigen::Ref<Matrix6Xd> J) {
  if (!c.enabled()) {
    walk(links, params, q, ParameterColumns(J));
    return;
  }
  JointVector joints;
  DeflectionJacobian deflection;
  deflect(links, c, params, q, joints, &deflection);
  Eigen::Ref<Matrix6Xd> geometric = J.leftCols(c.first_parameter);
  ParameterAndJointColumns::JointColumnsMatrix Jq(6, links.size());
  walk(links, params, joints, ParameterAndJointColumns(geometric, Jq));
  for (int p = 0; p < c.compliance->num_parameters(); ++p)
    J.col(c.first_parameter + p).noalias() = Jq * deflection.col(p);
}

/// J_pose_q (actuators' columns; a payload's zero) at the deflected joints, and the pose.
template <class Links>
Pose compliant_joint_columns(const Links& links, const ComplianceLayout& c, const ParamsRef& params,
                             const ActuatorsRef& q, Eigen::Ref<Matrix6Xd> J_pose_q) {
  J_pose_q.rightCols(J_pose_q.cols() - links.size()).setZero();
  Eigen::Ref<Matrix6Xd> joints = J_pose_q.leftCols(links.size());
  return walk_deflected(links, c, params, q, JointColumns(joints));
}

}  // namespace kincal::serial_chain
