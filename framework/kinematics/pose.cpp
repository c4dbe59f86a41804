#include "kincal/framework/kinematics/pose.hpp"

#include <Eigen/Geometry>
#include <algorithm>
#include <cmath>
#include <cstdint>
#include <cstring>

namespace kincal {

Matrix3d skew(const Vector3d& v) {
  Matrix3d S;
  S << 0.0, -v.z(), v.y(), v.z(), 0.0, -v.x(), -v.y(), v.x(), 0.0;
  return S;
}

namespace {

// exp_so3, inlined into perturb(): returned through memory, its matrix cost a store-forwarding
// stall per entry in the product that follows (a tenth of forward kinematics' time).
inline Matrix3d rodrigues(const Vector3d& w) {
  // Rodrigues: R = I + a [w]x + b [w]x^2 with a = sin(t)/t, b = (1 - cos(t))/t^2. Below
  // t = 1e-4 the series to t^4 is exact in double precision (the next terms are < 1e-17),
  // and it saves the sine and cosine in the last Newton steps of forward kinematics, whose
  // rotations are tiny.
  const double t2 = w.squaredNorm();
  double a, b;
  if (t2 < 1e-8) {
    a = 1.0 - t2 / 6.0 * (1.0 - t2 / 20.0);
    b = 0.5 - t2 / 24.0 * (1.0 - t2 / 30.0);
  } else {
    const double t = std::sqrt(t2);
    a = std::sin(t) / t;
    b = (1.0 - std::cos(t)) / t2;
  }
  // [w]x^2 = w w^T - t^2 I, written out: nine entries, no matrix products.
  const double c = 1.0 - b * t2;
  const Vector3d aw = a * w;
  Matrix3d R;
  R << c + b * w.x() * w.x(), b * w.x() * w.y() - aw.z(), b * w.x() * w.z() + aw.y(),
      b * w.x() * w.y() + aw.z(), c + b * w.y() * w.y(), b * w.y() * w.z() - aw.x(),
      b * w.x() * w.z() - aw.y(), b * w.y() * w.z() + aw.x(), c + b * w.z() * w.z();
  return R;
}

}  // namespace

Matrix3d exp_so3(const Vector3d& w) { return rodrigues(w); }

Vector3d log_so3(const Matrix3d& R) {
  const Eigen::AngleAxisd aa(R);
  return aa.angle() * aa.axis();
}

Matrix3d left_jacobian_so3(const Vector3d& w) {
  // Below t = 1e-4 the series to t^4 is exact in double precision (as in exp_so3); above,
  // the closed forms lose no more than a few ulps relative to their O(1) sum.
  const double t2 = w.squaredNorm();
  double b, c;  // (1 - cos t) / t^2, (t - sin t) / t^3
  if (t2 < 1e-8) {
    b = 0.5 - t2 / 24.0 * (1.0 - t2 / 30.0);
    c = 1.0 / 6.0 - t2 / 120.0 * (1.0 - t2 / 42.0);
  } else {
    const double t = std::sqrt(t2);
    b = (1.0 - std::cos(t)) / t2;
    c = (t - std::sin(t)) / (t2 * t);
  }
  const Matrix3d W = skew(w);
  return Matrix3d::Identity() + b * W + c * W * W;
}

Matrix3d left_jacobian_inverse_so3(const Vector3d& w) {
  const double t2 = w.squaredNorm();
  double c;  // 1 / t^2 - (1 + cos t) / (2 t sin t)
  if (t2 < 1e-8) {
    c = 1.0 / 12.0 + t2 / 720.0 * (1.0 + t2 / 42.0);
  } else {
    const double t = std::sqrt(t2);
    c = 1.0 / t2 - (1.0 + std::cos(t)) / (2.0 * t * std::sin(t));
  }
  const Matrix3d W = skew(w);
  return Matrix3d::Identity() - 0.5 * W + c * W * W;
}

Pose perturb(const Pose& pose, const Vector6d& delta) {
  Pose out;
  out.translation = pose.translation + delta.head<3>();
  out.rotation.noalias() = rodrigues(delta.tail<3>()) * pose.rotation;
  return out;
}

Pose inverse(const Pose& p) {
  Pose i;
  i.rotation = p.rotation.transpose();
  i.translation = -(i.rotation * p.translation);
  return i;
}

Vector3d euler_zyx(const Matrix3d& R) {
  // R = Rz(a) Ry(b) Rx(g): R(2,0) = -sin b, R(1,0)/R(0,0) = tan a, R(2,1)/R(2,2) = tan g.
  const double beta = std::asin(std::clamp(-R(2, 0), -1.0, 1.0));
  const double alpha = std::atan2(R(1, 0), R(0, 0));
  const double gamma = std::atan2(R(2, 1), R(2, 2));
  return Vector3d(alpha, beta, gamma);
}

Matrix3d rotation_from_euler_zyx(const Vector3d& abg) {
  return (Eigen::AngleAxisd(abg.x(), Vector3d::UnitZ()) *
          Eigen::AngleAxisd(abg.y(), Vector3d::UnitY()) *
          Eigen::AngleAxisd(abg.z(), Vector3d::UnitX()))
      .toRotationMatrix();
}

Pose frame_from_parameters(const Eigen::Ref<const VectorXd>& p) {
  Pose frame;
  frame.translation = p.head<3>();
  frame.rotation = rotation_from_euler_zyx(Vector3d(p[5], p[4], p[3]));
  return frame;
}

Vector6d frame_parameters(const Pose& frame) {
  const Vector3d zyx = euler_zyx(frame.rotation);
  Vector6d p;
  p << frame.translation, zyx[2], zyx[1], zyx[0];
  return p;
}

Matrix3d euler_zyx_angular_jacobian(const Vector3d& rx_ry_rz) {
  // dR/drz = [ez]x R; dR/dry = Rz [ey]x Ry Rx = [Rz ey]x R; dR/drx = [Rz Ry ex]x R.
  const Matrix3d Rz = Eigen::AngleAxisd(rx_ry_rz[2], Vector3d::UnitZ()).toRotationMatrix();
  const Matrix3d RzRy = Rz * Eigen::AngleAxisd(rx_ry_rz[1], Vector3d::UnitY()).toRotationMatrix();
  Matrix3d J;
  J.col(0) = RzRy.col(0);
  J.col(1) = Rz.col(1);
  J.col(2) = Vector3d::UnitZ();
  return J;
}

namespace {

// The frame blocks this thread computed last, in a direct-mapped table keyed by their six
// values' bits (so -0.0 and 0.0, or two NaNs of different payloads, are different keys: a
// hit returns exactly what computing would). Plain numbers, so that the thread-local table
// needs no constructor call on each access.
struct FrameBlockTable {
  static constexpr int kEntries = 64;  // a 6-axis arm with two trackers uses about 10
  struct Entry {
    std::uint64_t key[6];
    double rotation[9], translation[3], angular_jacobian[9];
    bool used;
  };
  Entry entries[kEntries];
};

}  // namespace

FrameBlock frame_block(const double* p) {
  thread_local FrameBlockTable table;
  std::uint64_t key[6];
  std::memcpy(key, p, sizeof key);
  std::uint64_t hash = 0;
  for (const std::uint64_t word : key) hash = (hash ^ word) * 0x9E3779B97F4A7C15ull;
  FrameBlockTable::Entry& entry = table.entries[hash >> 58];  // the top 6 bits: 0 .. 63
  FrameBlock block;
  if (entry.used && std::memcmp(entry.key, key, sizeof key) == 0) {
    block.frame.rotation = Eigen::Map<const Matrix3d>(entry.rotation);
    block.frame.translation = Eigen::Map<const Vector3d>(entry.translation);
    block.angular_jacobian = Eigen::Map<const Matrix3d>(entry.angular_jacobian);
    return block;
  }
  const Eigen::Map<const Vector6d> values(p);
  block.frame = frame_from_parameters(values);
  block.angular_jacobian = euler_zyx_angular_jacobian(values.tail<3>());
  std::memcpy(entry.key, key, sizeof key);
  Eigen::Map<Matrix3d>(entry.rotation) = block.frame.rotation;
  Eigen::Map<Vector3d>(entry.translation) = block.frame.translation;
  Eigen::Map<Matrix3d>(entry.angular_jacobian) = block.angular_jacobian;
  entry.used = true;
  return block;
}

double position_error(const Pose& a, const Pose& b) {
  return (a.translation - b.translation).norm();
}

double orientation_error(const Pose& reference, const Pose& other) {
  return euler_zyx(reference.rotation.transpose() * other.rotation).norm();
}

}  // namespace kincal
