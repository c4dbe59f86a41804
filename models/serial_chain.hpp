#pragma once
// What every serial chain shares, whatever its link parametrisation (the DH/Hayati arm, the
// URDF arm): the walk from base to tool that gives forward kinematics, J_pose_params and
// J_pose_q in one pass, the Jacobian columns of elementary motions, the columns of a
// six-parameter frame block, the frame parameters' names, and the inverse kinematics. An arm
// keeps only its links: how one link moves the frame and which elementary motion each of its
// parameters is (a Links policy of walk below).
//
// Jacobian columns are built in the "moment" form while walking from base to tool: a rotation
// about the unit axis w through the point o is the column [o x w; w], a translation along u is
// [u; 0]; once the end's position t_end is known, finish_columns() adds w x t_end to the
// translation rows, giving the end's motion [w x (t_end - o); w]. One pass, no 3 x n product.

#include <Eigen/Cholesky>
#include <algorithm>
#include <cmath>
#include <string>
#include <vector>

#include "kincal/framework/kinematics/mechanism.hpp"
#include "kincal/framework/kinematics/parameters.hpp"
#include "kincal/framework/kinematics/pose.hpp"

namespace kincal {

/// Options of serial_chain::inverse_kinematics (SerialArm::inverse_kinematics_from,
/// UrdfArm::inverse_kinematics_from).
struct SerialInverseKinematicsOptions {
  int max_iterations = 200;
  /// Solved when the position error is below this (mm) and the rotation error below
  /// rotation_tolerance (rad).
  double position_tolerance = 1e-9;
  double rotation_tolerance = 1e-12;
  /// Rotation errors are weighted by this length (mm per rad) against position errors, so
  /// that 1 mrad counts like 1 mm at 1 m.
  double rotation_weight = 1000.0;
};

namespace serial_chain {

/// The column of a rotation about the unit axis w through o, in the moment form.
template <class Column>
void rotation_column(Column&& column, const Vector3d& w, const Vector3d& o) {
  column.template head<3>() = o.cross(w);
  column.template tail<3>() = w;
}

/// The column of a translation along `direction`.
template <class Column>
void translation_column(Column&& column, const Vector3d& direction) {
  column.template head<3>() = direction;
  column.template tail<3>().setZero();
}

/// Adds w x t_end to the translation rows of every column (nothing for translations, whose w
/// is zero). Column by column: a 3 x 3 times 3 x n product would go through Eigen's general
/// product, which may allocate.
inline void finish_columns(Eigen::Ref<Matrix6Xd>& J, const Vector3d& t_end) {
  for (Eigen::Index c = 0; c < J.cols(); ++c) J.col(c).head<3>() += J.col(c).tail<3>().cross(t_end);
}

/// The six columns of a frame block (x, y, z, then Z-Y-X Euler angles whose angular Jacobian
/// is `angular`, euler_zyx_angular_jacobian) that follows the frame `parent` and ends at
/// `after`: its translations move everything beyond it along the parent's axes; its angles
/// turn everything beyond it about parent.R `angular` through the block's own origin
/// (after's).
template <class Block>
void frame_block_columns(Block&& J, const Pose& parent, const Pose& after,
                         const Matrix3d& angular) {
  J.template topLeftCorner<3, 3>() = parent.rotation;
  J.template bottomLeftCorner<3, 3>().setZero();
  const Matrix3d W = parent.rotation * angular;
  for (int k = 0; k < 3; ++k) rotation_column(J.col(3 + k), W.col(k), after.translation);
}

/// What walk() does with the elementary motions it passes: nothing (forward kinematics, and
/// the base of the records below). A record has these members; walk is a template over it,
/// so that an empty one costs nothing.
struct PoseOnly {
  /// Parameter `column` turns the end about the unit axis w through o.
  void parameter_rotation(int /*column*/, const Vector3d& /*w*/, const Vector3d& /*o*/) {}
  /// Parameter `column` moves the end along u.
  void parameter_translation(int /*column*/, const Vector3d& /*u*/) {}
  /// Parameters first_column .. + 5 are a frame block whose angles' angular Jacobian is
  /// `angular`, that follows the frame `parent` and ends at `after` (frame_block_columns).
  void parameter_frame(int /*first_column*/, const Pose& /*parent*/, const Pose& /*after*/,
                       const Matrix3d& /*angular*/) {}
  /// Joint i turns the end about the unit axis through `origin` (revolute) or moves it
  /// along the axis (prismatic).
  void joint(int /*i*/, bool /*revolute*/, const Vector3d& /*axis*/, const Vector3d& /*origin*/) {}
  /// Link i's frame once joint i has moved (the frame of the joint's child link).
  void link(int /*i*/, const Pose& /*frame*/) {}
  /// The walk is done: `tip` is the frame the tool block follows, `end` the chain's end.
  void finish(const Pose& /*tip*/, const Pose& /*end*/) {}
};

/// Records J_pose_params: a column per parameter, in the parameter layout.
class ParameterColumns : public PoseOnly {
 public:
  explicit ParameterColumns(Eigen::Ref<Matrix6Xd>& J) : J_(J) {}
  void parameter_rotation(int column, const Vector3d& w, const Vector3d& o) {
    rotation_column(J_.col(column), w, o);
  }
  void parameter_translation(int column, const Vector3d& u) {
    translation_column(J_.col(column), u);
  }
  void parameter_frame(int first_column, const Pose& parent, const Pose& after,
                       const Matrix3d& angular) {
    frame_block_columns(J_.middleCols<6>(first_column), parent, after, angular);
  }
  void finish(const Pose&, const Pose& end) { finish_columns(J_, end.translation); }

 private:
  Eigen::Ref<Matrix6Xd>& J_;
};

/// Records J_pose_q: a column per joint.
class JointColumns : public PoseOnly {
 public:
  explicit JointColumns(Eigen::Ref<Matrix6Xd>& J) : J_(J) {}
  void joint(int i, bool revolute, const Vector3d& axis, const Vector3d& origin) {
    if (revolute)
      rotation_column(J_.col(i), axis, origin);
    else
      translation_column(J_.col(i), axis);
  }
  void finish(const Pose&, const Pose& end) { finish_columns(J_, end.translation); }

 private:
  Eigen::Ref<Matrix6Xd>& J_;
};

/// The walk from base to tool of a serial chain
///
///   T(q) = B  L_1(q_1) ... L_N(q_N)  C_tip  T_tool
///
/// with the base frame block B in parameters 0 .. 5 and the tool frame block T_tool in the
/// last six, links.tool_index() .. + 5 (frame_block, both). The links are the
/// arm's own; `links` is a small policy with
///
///   int size() const                          N
///   int tool_index() const                    the tool block's first parameter
///   template <class Record>
///   void advance(int i, const ParamsRef& params, double q_i, Pose& frame, Record& record) const
///                                             moves `frame` across link i (joint i at q_i
///                                             included) and tells `record` the elementary
///                                             motion of each of the link's parameters and of
///                                             the joint (PoseOnly's members)
///   void to_tip(Pose& frame) const            C_tip (identity: nothing)
///
/// Returns the end's pose; `record` (PoseOnly, ParameterColumns, JointColumns or the caller's
/// own) gets the columns and, last, finish(). Fixed-size types, nothing allocated. Always
/// inlined into the caller, which makes the record and the links: out of line (its
/// instantiations with these shared records are not local to one file, so GCC does not inline
/// them by itself) the record's Jacobian would be reloaded from memory after every call to
/// sin and cos, 1-3 % more instructions per walk than with the record in registers.
template <class Links, class Record>
__attribute__((always_inline)) inline Pose walk(const Links& links, const ParamsRef& params,
                                                const ActuatorsRef& q, Record&& record) {
  const FrameBlock base = frame_block(params.segment<6>(0));
  Pose frame = base.frame;
  record.parameter_frame(0, Pose{}, frame, base.angular_jacobian);
  const int n = links.size();
  for (int i = 0; i < n; ++i) links.advance(i, params, q[i], frame, record);
  links.to_tip(frame);
  const int tool_index = links.tool_index();
  const FrameBlock tool = frame_block(params.segment<6>(tool_index));
  Pose end;
  end.rotation = frame.rotation * tool.frame.rotation;
  end.translation = frame.translation + frame.rotation * tool.frame.translation;
  // The tool's rotation turns the end about its own origin: no translation.
  record.parameter_frame(tool_index, frame, end, tool.angular_jacobian);
  record.finish(frame, end);
  return end;
}

/// Appends a frame block's six parameters, `prefix`.x, .y, .z (mm), .rx, .ry, .rz (rad).
void add_frame_parameters(std::vector<Parameter>& out, const std::string& prefix,
                          const Vector6d& values);

/// The joint values that put a chain's end at `target`, by Levenberg-Marquardt on the
/// weighted pose error [t_target - t; w log(R_target R^T)], from `start`. `pose_at(q)` is
/// the end's pose; `joint_jacobian(q, J)` fills the 6 x n J_pose_q and returns the pose.
/// An unreachable target is a status with a reason and the closest joint values found.
template <class PoseAt, class JointJacobian>
InverseKinematicsResult inverse_kinematics(const Pose& target, const ActuatorsRef& start,
                                           Eigen::Ref<VectorXd> q,
                                           const SerialInverseKinematicsOptions& options,
                                           PoseAt&& pose_at, JointJacobian&& joint_jacobian);

/// The weighted pose error [t_target - t; w log(R_target R^T)]: the perturbation (pose.hpp)
/// that takes the current pose to the target, rotation scaled to mm.
Vector6d pose_error(const Pose& target, const Pose& current, double rotation_weight);
/// "0.1 mm and 0.002 rad": the size of a pose error, in words.
std::string pose_error_text(const Vector6d& e, double rotation_weight);
/// The reason of an inverse kinematics that stopped short (see inverse_kinematics).
void describe_inverse_kinematics_failure(InverseKinematicsResult& result, const Vector6d& e,
                                         double rotation_weight, int joints, bool stationary);

template <class PoseAt, class JointJacobian>
InverseKinematicsResult inverse_kinematics(const Pose& target, const ActuatorsRef& start,
                                           Eigen::Ref<VectorXd> q,
                                           const SerialInverseKinematicsOptions& options,
                                           PoseAt&& pose_at, JointJacobian&& joint_jacobian) {
  InverseKinematicsResult result;
  const auto n = start.size();
  if (!target.rotation.allFinite() || !target.translation.allFinite() || !start.allFinite()) {
    result.status = InverseKinematicsStatus::kNonFinite;
    q = start;
    return result;
  }
  const double w = options.rotation_weight;
  const auto solved = [&](const Vector6d& e) {
    return e.head<3>().norm() <= options.position_tolerance &&
           e.tail<3>().norm() <= w * options.rotation_tolerance;
  };
  Matrix6Xd J(6, n);
  VectorXd x = start, trial(n), step(n);
  MatrixXd A(n, n);
  VectorXd g(n);
  Vector6d e = pose_error(target, joint_jacobian(x, J), w);
  double cost = e.squaredNorm();
  double lambda = -1;  // set from the first Jacobian's scale
  bool stationary = false;
  for (result.iterations = 0; result.iterations < options.max_iterations && !solved(e);
       ++result.iterations) {
    J.bottomRows<3>() *= w;
    A.noalias() = J.transpose() * J;
    g.noalias() = J.transpose() * e;
    const double scale = A.diagonal().maxCoeff();
    if (!(scale > 0) || !std::isfinite(scale)) {  // no joint moves the end: nothing to do
      stationary = true;
      break;
    }
    if (lambda < 0) lambda = 1e-3 * scale;
    // Grow the damping until a step lowers the cost. A cost that no step lowers, even tiny,
    // is a stationary point of the pose error.
    bool accepted = false;
    while (!accepted) {
      A.diagonal().array() += lambda;
      step = A.ldlt().solve(g);
      A.diagonal().array() -= lambda;
      trial = x + step;
      const double cost_trial = pose_error(target, pose_at(trial), w).squaredNorm();
      if (cost_trial < cost) {
        accepted = true;
        x = trial;
        lambda = std::max(lambda / 3, 1e-12 * scale);
        if (step.norm() <= 1e-15 * (1 + x.norm()) || cost - cost_trial <= 1e-15 * cost)
          stationary = true;
      } else {
        lambda *= 4;
        if (lambda > 1e12 * scale) {
          stationary = true;
          break;
        }
      }
    }
    e = pose_error(target, joint_jacobian(x, J), w);
    cost = e.squaredNorm();
    if (stationary && !solved(e)) break;
  }
  q = x;  // the solution, or the closest joint values found
  result.residual_norm = e.head<3>().norm() + e.tail<3>().norm() / w;
  if (!solved(e))
    describe_inverse_kinematics_failure(result, e, w, static_cast<int>(n), stationary);
  return result;
}

}  // namespace serial_chain
}  // namespace kincal
