#pragma once
// Automatic derivatives (forward mode): write a sensor's readings, a closed chain's
// constraints or a serial link's transform once, as a function template of the scalar type,
// and derive from the matching base class below; it implements every Jacobian the
// interfaces need by evaluating the template on dual numbers (Eigen's AutoDiffScalar with a
// fixed-size derivative vector, so nothing is allocated per configuration; why this one and
// not Ceres' Jet: docs/architecture.md). Hand-written Jacobians stay possible: a type that
// overrides the virtual functions itself does not use this header at all.
//
//   AutoDiffSensor<Derived, NumParameters, NumReadings>
//       Derived::autodiff_readings<T>(const T* params, const PoseT<T>& pose, T* readings)
//   AutoDiffClosedChain<Derived, Dof>
//       Derived::autodiff_constraints<T>(const T* params, const ActuatorsRef& q,
//                                        const PoseT<T>& pose, T* g)
//   AutoDiffSerialChain<Derived, LinkParameters>
//       Derived::autodiff_link<T>(int joint, const T* link_params, const T& q) -> PoseT<T>
//
// Inside the templates, write scalar functions unqualified after `using std::cos;` (and
// sin, sqrt, atan2, ...), so that argument-dependent lookup finds Eigen's overloads for
// the dual numbers; kincal::ad::rot_x/rot_y/rot_z/translation/frame build poses.
// Derivatives are exact (to rounding), so the finite-difference checks of the hand-written
// types apply unchanged (tests/models/autodiff_test.cpp).

#include <Eigen/Core>
#include <array>
#include <unsupported/Eigen/AutoDiff>
#include <vector>

#include "kincal/framework/kinematics/closed_chain_mechanism.hpp"
#include "kincal/framework/kinematics/sensor.hpp"

namespace kincal {

/// A dual number carrying N partial derivatives (fixed size: no allocation).
template <int N>
using Jet = Eigen::AutoDiffScalar<Eigen::Matrix<double, N, 1>>;

/// A rigid pose over any scalar (Pose is PoseT<double>'s plain counterpart).
template <class T>
struct PoseT {
  Eigen::Matrix<T, 3, 3> rotation = Eigen::Matrix<T, 3, 3>::Identity();
  Eigen::Matrix<T, 3, 1> translation = Eigen::Matrix<T, 3, 1>::Zero();

  /// R p + t. Written out: Eigen's generic product does not unroll over dual numbers (their
  /// cost exceeds its unrolling limit) and would call a kernel per coefficient.
  template <class Vector>
  Eigen::Matrix<T, 3, 1> transform_point(const Vector& p) const {
    Eigen::Matrix<T, 3, 1> out;
    for (int i = 0; i < 3; ++i)
      out[i] =
          rotation(i, 0) * p[0] + rotation(i, 1) * p[1] + rotation(i, 2) * p[2] + translation[i];
    return out;
  }
  /// Composition: (this * other).transform_point(p) = transform_point(other.transform_point(p)).
  PoseT operator*(const PoseT& other) const {
    PoseT out;
    for (int i = 0; i < 3; ++i) {
      for (int j = 0; j < 3; ++j)
        out.rotation(i, j) = rotation(i, 0) * other.rotation(0, j) +
                             rotation(i, 1) * other.rotation(1, j) +
                             rotation(i, 2) * other.rotation(2, j);
      out.translation[i] = rotation(i, 0) * other.translation[0] +
                           rotation(i, 1) * other.translation[1] +
                           rotation(i, 2) * other.translation[2] + translation[i];
    }
    return out;
  }
};

namespace ad {

inline double value(double x) { return x; }
template <class D>
double value(const Eigen::AutoDiffScalar<D>& x) {
  return x.value();
}
template <int N>
Eigen::Matrix<double, N, 1>& grad(Jet<N>& x) {
  return x.derivatives();
}
template <int N>
const Eigen::Matrix<double, N, 1>& grad(const Jet<N>& x) {
  return x.derivatives();
}

/// The number of derivatives to carry for n: n rounded up to a multiple of 4. GCC inlines
/// the derivative arithmetic of 4 and 8 doubles (whole SSE/AVX packets) but calls a kernel
/// per operation for 6, which made the 6-DOF evaluations twice as slow (docs/benchmarks.md).
constexpr int padded(int n) { return (n + 3) / 4 * 4; }

/// A constant: value v, every derivative zero.
template <int N>
Jet<N> constant(double v) {
  return Jet<N>(v, Eigen::Matrix<double, N, 1>::Zero());
}

/// The elementary rotations and translations, for writing link transforms and frames.
template <class T>
PoseT<T> rot_x(const T& angle) {
  using std::cos;
  using std::sin;
  PoseT<T> p;
  const T c = cos(angle), s = sin(angle);
  p.rotation(1, 1) = c, p.rotation(1, 2) = -s;
  p.rotation(2, 1) = s, p.rotation(2, 2) = c;
  return p;
}
template <class T>
PoseT<T> rot_y(const T& angle) {
  using std::cos;
  using std::sin;
  PoseT<T> p;
  const T c = cos(angle), s = sin(angle);
  p.rotation(0, 0) = c, p.rotation(0, 2) = s;
  p.rotation(2, 0) = -s, p.rotation(2, 2) = c;
  return p;
}
template <class T>
PoseT<T> rot_z(const T& angle) {
  using std::cos;
  using std::sin;
  PoseT<T> p;
  const T c = cos(angle), s = sin(angle);
  p.rotation(0, 0) = c, p.rotation(0, 1) = -s;
  p.rotation(1, 0) = s, p.rotation(1, 1) = c;
  return p;
}
template <class T>
PoseT<T> translation(const T& x, const T& y, const T& z) {
  PoseT<T> p;
  p.translation << x, y, z;
  return p;
}
/// A frame parameter block [x, y, z, rx, ry, rz] (pose.hpp's frame_from_parameters).
template <class T>
PoseT<T> frame(const T* p) {
  PoseT<T> f = rot_z(p[5]) * rot_y(p[4]) * rot_x(p[3]);
  f.translation << p[0], p[1], p[2];
  return f;
}

/// The pose as PoseT<double>, and back.
inline PoseT<double> to_pose_t(const Pose& pose) { return {pose.rotation, pose.translation}; }
inline Pose to_pose(const PoseT<double>& pose) { return {pose.rotation, pose.translation}; }
template <int N>
Pose value(const PoseT<Jet<N>>& pose) {
  Pose out;
  for (int r = 0; r < 3; ++r) {
    out.translation[r] = ad::value(pose.translation[r]);
    for (int c = 0; c < 3; ++c) out.rotation(r, c) = ad::value(pose.rotation(r, c));
  }
  return out;
}

/// `pose` perturbed by delta = basis * s (pose.hpp's convention) as dual numbers whose
/// derivatives offset..offset+Dof-1 are those with respect to s, at s = 0. First order is
/// enough: t + dt and (I + [dw]x) R have the derivatives of t + dt and exp([dw]x) R at 0.
template <int N, int Dof>
PoseT<Jet<N>> perturbed(const Pose& pose, const Eigen::Matrix<double, 6, Dof>& basis, int offset) {
  PoseT<Jet<N>> out;
  for (int i = 0; i < 3; ++i) {
    out.translation[i] = constant<N>(pose.translation[i]);
    ad::grad(out.translation[i]).template segment<Dof>(offset) = basis.row(i).transpose();
  }
  // d(R e_j)/d(dw) = d(dw x c_j)/d(dw) = -[c_j]x, c_j the column j of R.
  for (int j = 0; j < 3; ++j) {
    const Eigen::Matrix<double, 3, Dof> d = -skew(pose.rotation.col(j)) * basis.bottomRows(3);
    for (int i = 0; i < 3; ++i) {
      out.rotation(i, j) = constant<N>(pose.rotation(i, j));
      ad::grad(out.rotation(i, j)).template segment<Dof>(offset) = d.row(i).transpose();
    }
  }
  return out;
}

/// Column k (k < count, derivative offset + k) of the pose perturbation [dt; dw] of a
/// dual-number pose: dt = dt/ds_k, dw = vee(dR/ds_k R^T) (antisymmetric part).
template <int N>
Vector6d tangent(const PoseT<Jet<N>>& pose, const Matrix3d& R, int k) {
  Vector6d out;
  Matrix3d dR;
  for (int i = 0; i < 3; ++i) {
    out[i] = ad::grad(pose.translation[i])[k];
    for (int j = 0; j < 3; ++j) dR(i, j) = ad::grad(pose.rotation(i, j))[k];
  }
  const Matrix3d W = dR * R.transpose();
  out.tail<3>() << 0.5 * (W(2, 1) - W(1, 2)), 0.5 * (W(0, 2) - W(2, 0)), 0.5 * (W(1, 0) - W(0, 1));
  return out;
}

/// A per-thread array of n dual numbers, reused between calls (grows, never shrinks), so
/// that a parameter vector of run-time size needs no allocation per configuration.
template <int N>
std::vector<Jet<N>>& scratch(int n) {
  thread_local std::vector<Jet<N>> buffer;
  if (static_cast<int>(buffer.size()) < n) buffer.resize(n);
  return buffer;
}

}  // namespace ad

/// A sensor with NumParameters parameters and NumReadings plain readings (reading_error is
/// predicted - measured) whose predict() derives both Jacobians from
///   template <class T> void autodiff_readings(const T* params, const PoseT<T>& pose,
///                                             T* readings) const;
/// in one evaluation on dual numbers with 6 + NumParameters derivatives (padded).
template <class Derived, int NumParameters, int NumReadings>
class AutoDiffSensor : public Sensor {
 public:
  static constexpr int kNumParameters = NumParameters;
  static constexpr int kNumReadings = NumReadings;
  static constexpr int kDerivatives = ad::padded(6 + NumParameters);
  using Dual = Jet<kDerivatives>;

  int num_readings() const override { return NumReadings; }

  void predict(const Eigen::Ref<const VectorXd>& params, const Pose& pose,
               Eigen::Ref<VectorXd> reading, MatrixXd* J_reading_pose,
               MatrixXd* J_reading_params) const override {
    eigen_assert(params.size() == NumParameters && reading.size() == NumReadings);
    const Derived& self = static_cast<const Derived&>(*this);
    if (!J_reading_pose && !J_reading_params) {
      self.autodiff_readings(params.data(), ad::to_pose_t(pose), reading.data());
      return;
    }
    std::array<Dual, NumParameters> p;
    for (int k = 0; k < NumParameters; ++k) {
      p[k] = ad::constant<kDerivatives>(params[k]);
      ad::grad(p[k])[6 + k] = 1.0;
    }
    const PoseT<Dual> x = ad::perturbed<kDerivatives, 6>(pose, Matrix6d::Identity(), 0);
    std::array<Dual, NumReadings> out;
    self.autodiff_readings(p.data(), x, out.data());
    for (int r = 0; r < NumReadings; ++r) {
      reading[r] = ad::value(out[r]);
      if (J_reading_pose) J_reading_pose->row(r) = ad::grad(out[r]).template head<6>().transpose();
      if (J_reading_params)
        J_reading_params->row(r) = ad::grad(out[r]).template segment<NumParameters>(6).transpose();
    }
  }
};

/// A closed chain whose constraint functions and both constraint Jacobians come from
///   template <class T> void autodiff_constraints(const T* params, const ActuatorsRef& q,
///                                                const PoseT<T>& pose, T* g) const;
/// J_g_pose: one evaluation with Dof derivatives (the local pose coordinates); J_g_params:
/// one evaluation per Chunk parameters (a run-time number of them, in per-thread scratch).
/// Forward kinematics, the pose Jacobians and the adjoint output Jacobian are
/// ClosedChainMechanism's, unchanged.
template <class Derived, int Dof, int Chunk = 8>
class AutoDiffClosedChain : public ClosedChainMechanism<Dof> {
  using Base = ClosedChainMechanism<Dof>;

 public:
  using typename Base::ConstraintJacobian;
  using typename Base::ConstraintVector;
  using typename Base::ParamsJacobian;
  static constexpr int kPoseDerivatives = ad::padded(Dof);

  void constraints(const ParamsRef& params, const ActuatorsRef& q, const Pose& pose,
                   ConstraintVector& g, ConstraintJacobian* J_g_pose) const override {
    const Derived& self = static_cast<const Derived&>(*this);
    if (!J_g_pose) {
      self.autodiff_constraints(params.data(), q, ad::to_pose_t(pose), g.data());
      return;
    }
    constexpr int N = kPoseDerivatives;
    std::vector<Jet<N>>& p = ad::scratch<N>(static_cast<int>(params.size()));
    for (Eigen::Index k = 0; k < params.size(); ++k) p[k] = ad::constant<N>(params[k]);
    const PoseT<Jet<N>> x = ad::perturbed<N, Dof>(pose, this->motion_basis(), 0);
    std::array<Jet<N>, Dof> out;
    self.autodiff_constraints(p.data(), q, x, out.data());
    for (int i = 0; i < Dof; ++i) {
      g[i] = ad::value(out[i]);
      J_g_pose->row(i) = ad::grad(out[i]).template head<Dof>().transpose();
    }
  }

  void constraint_jacobian_params(const ParamsRef& params, const ActuatorsRef& q, const Pose& pose,
                                  Eigen::Ref<ParamsJacobian> J_g_params) const override {
    const Derived& self = static_cast<const Derived&>(*this);
    const int n = static_cast<int>(params.size());
    std::vector<Jet<Chunk>>& p = ad::scratch<Chunk>(n);
    for (int k = 0; k < n; ++k) p[k] = ad::constant<Chunk>(params[k]);
    PoseT<Jet<Chunk>> x;
    for (int i = 0; i < 3; ++i) {
      x.translation[i] = ad::constant<Chunk>(pose.translation[i]);
      for (int j = 0; j < 3; ++j) x.rotation(i, j) = ad::constant<Chunk>(pose.rotation(i, j));
    }
    std::array<Jet<Chunk>, Dof> out;
    for (int start = 0; start < n; start += Chunk) {
      const int count = std::min(Chunk, n - start);
      for (int k = 0; k < count; ++k) ad::grad(p[start + k])[k] = 1.0;
      self.autodiff_constraints(p.data(), q, x, out.data());
      for (int i = 0; i < Dof; ++i)
        J_g_params.row(i).segment(start, count) = ad::grad(out[i]).head(count).transpose();
      for (int k = 0; k < count; ++k) ad::grad(p[start + k])[k] = 0.0;
    }
  }

 protected:
  AutoDiffClosedChain() = default;
  template <int D = Dof, typename = std::enable_if_t<(D < 6)>>
  explicit AutoDiffClosedChain(const typename Base::MotionBasis& basis) : Base(basis) {}
};

/// A serial chain T(q) = B A_1(q_1) ... A_N(q_N) E: base and tool frame blocks
/// [x, y, z, rx, ry, rz] (ad::frame) around N links of LinkParameters parameters each, in
/// that order in the parameter vector, with
///   int num_joints() const;
///   template <class T> PoseT<T> autodiff_link(int joint, const T* link_params,
///                                             const T& q) const;
/// Forward kinematics is the product; J_pose_params and the joint Jacobian take each
/// block's derivatives on dual numbers of its own size and move them to the end pose
/// (a block's perturbation [dt; dw] in its parent frame P moves the end by
/// R_P dt + (R_P dw) x (t_end - t_P - R_P t_block) and turns it by R_P dw).
template <class Derived, int LinkParameters>
class AutoDiffSerialChain : public Mechanism {
 public:
  static constexpr int kFrameParameters = 6;
  static constexpr int kLinkParameters = LinkParameters;
  static int joint_index(int joint) { return kFrameParameters + LinkParameters * joint; }

  ForwardKinematicsResult forward_kinematics(const ParamsRef& params, const ActuatorsRef& q,
                                             const Pose&,
                                             const ForwardKinematicsOptions& = {}) const override {
    ForwardKinematicsResult result;
    if (!q.allFinite()) {
      result.status = ForwardKinematicsStatus::kInvalidActuators;
      return result;
    }
    result.pose = end_pose(params, q);
    if (!result.pose.rotation.allFinite() || !result.pose.translation.allFinite()) {
      result.status = ForwardKinematicsStatus::kNonFinite;
      result.pose = Pose{};
    }
    return result;
  }

  void pose_jacobian_params(const ParamsRef& params, const ActuatorsRef& q, const Pose&,
                            Eigen::Ref<Matrix6Xd> J_pose_params) const override {
    const Derived& self = static_cast<const Derived&>(*this);
    const Pose end = end_pose(params, q);
    const int joints = self.num_joints();
    PoseT<double> prefix;
    // Base and tool: a frame block over six dual numbers (eight derivatives: see
    // ad::padded).
    auto frame_block = [&](int index) {
      constexpr int N = ad::padded(6);
      std::array<Jet<N>, 6> p;
      for (int k = 0; k < 6; ++k) {
        p[k] = ad::constant<N>(params[index + k]);
        ad::grad(p[k])[k] = 1.0;
      }
      const PoseT<Jet<N>> block = ad::frame(p.data());
      move_to_end<6>(prefix, block, end, J_pose_params.template middleCols<6>(index));
      return ad::to_pose_t(ad::value(block));
    };
    prefix = frame_block(0);
    for (int i = 0; i < joints; ++i) {
      const int index = joint_index(i);
      constexpr int N = ad::padded(LinkParameters);
      std::array<Jet<N>, LinkParameters> p;
      for (int k = 0; k < LinkParameters; ++k) {
        p[k] = ad::constant<N>(params[index + k]);
        ad::grad(p[k])[k] = 1.0;
      }
      const PoseT<Jet<N>> link = self.autodiff_link(i, p.data(), ad::constant<N>(q[i]));
      move_to_end<LinkParameters>(prefix, link, end,
                                  J_pose_params.template middleCols<LinkParameters>(index));
      prefix = prefix * ad::to_pose_t(ad::value(link));
    }
    frame_block(joint_index(joints));
  }

  /// The joint Jacobian J_pose_q (6 x N) and the pose at q.
  Pose joint_jacobian(const ParamsRef& params, const ActuatorsRef& q,
                      Eigen::Ref<Matrix6Xd> J_pose_q) const {
    const Derived& self = static_cast<const Derived&>(*this);
    const Pose end = end_pose(params, q);
    PoseT<double> prefix = ad::frame(params.data());
    for (int i = 0; i < self.num_joints(); ++i) {
      std::array<Jet<1>, LinkParameters> p;
      for (int k = 0; k < LinkParameters; ++k) p[k] = ad::constant<1>(params[joint_index(i) + k]);
      Jet<1> qi = ad::constant<1>(q[i]);
      ad::grad(qi)[0] = 1.0;
      const PoseT<Jet<1>> link = self.autodiff_link(i, p.data(), qi);
      move_to_end<1>(prefix, link, end, J_pose_q.col(i));
      prefix = prefix * ad::to_pose_t(ad::value(link));
    }
    return end;
  }

 private:
  Pose end_pose(const ParamsRef& params, const ActuatorsRef& q) const {
    const Derived& self = static_cast<const Derived&>(*this);
    PoseT<double> pose = ad::frame(params.data());
    for (int i = 0; i < self.num_joints(); ++i)
      pose = pose * self.autodiff_link(i, params.data() + joint_index(i), q[i]);
    return ad::to_pose(pose * ad::frame(params.data() + joint_index(self.num_joints())));
  }

  /// Columns 0..Count-1 of J: the derivatives 0..Count-1 of `block` moved to the end pose.
  template <int Count, int N, class Columns>
  static void move_to_end(const PoseT<double>& prefix, const PoseT<Jet<N>>& block, const Pose& end,
                          Columns&& J) {
    const Pose value = ad::value(block);
    // Where the end sits relative to the block's origin, in the prefix's frame.
    const Vector3d lever =
        prefix.rotation.transpose() * (end.translation - prefix.translation) - value.translation;
    for (int k = 0; k < Count; ++k) {
      const Vector6d local = ad::tangent(block, value.rotation, k);
      const Vector3d w = prefix.rotation * local.tail<3>();
      J.col(k).template head<3>() =
          prefix.rotation * (local.head<3>() + local.tail<3>().cross(lever));
      J.col(k).template tail<3>() = w;
    }
  }
};

}  // namespace kincal
