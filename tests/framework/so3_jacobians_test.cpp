// The SO(3) Jacobians of pose.hpp against finite differences of exp_so3 and log_so3, across
// the switch to the series at 1e-4 rad and up to near a half turn.

#include <gtest/gtest.h>

#include "jacobian_check.hpp"
#include "kincal/framework/base/random.hpp"
#include "kincal/framework/kinematics/pose.hpp"

namespace kincal {
namespace {

using kincal::testing::jacobians_match;
using kincal::testing::numerical_jacobian;

std::vector<Vector3d> rotation_vectors() {
  std::vector<Vector3d> out = {Vector3d::Zero()};
  Random rng(21);
  for (double angle : {1e-9, 5e-5, 9.9e-5, 1.01e-4, 1e-3, 0.3, 1.0, 2.0, 3.0}) {
    for (int i = 0; i < 4; ++i) {
      Vector3d axis(rng.symmetric(1.0), rng.symmetric(1.0), rng.symmetric(1.0));
      out.push_back(angle * axis.normalized());
    }
  }
  return out;
}

TEST(So3Jacobians, LeftJacobianIsTheDerivativeOfExpAsALeftPerturbation) {
  // exp(w + e) exp(w)^T = exp(J_l(w) e) to first order: d/de log(exp(w + e) exp(w)^T) = J_l.
  for (const Vector3d& w : rotation_vectors()) {
    const Matrix3d R_inverse = exp_so3(w).transpose();
    auto f = [&](const VectorXd& e) -> VectorXd {
      return log_so3(exp_so3(w + Vector3d(e)) * R_inverse);
    };
    EXPECT_TRUE(
        jacobians_match(left_jacobian_so3(w), numerical_jacobian(f, VectorXd::Zero(3), 1e-6), 1e-8))
        << "w = " << w.transpose();
  }
}

TEST(So3Jacobians, InverseLeftJacobianIsTheDerivativeOfLogUnderALeftPerturbation) {
  // log(exp(d) exp(w)) = w + J_l^-1(w) d to first order.
  for (const Vector3d& w : rotation_vectors()) {
    const Matrix3d R = exp_so3(w);
    auto f = [&](const VectorXd& d) -> VectorXd { return log_so3(exp_so3(Vector3d(d)) * R); };
    EXPECT_TRUE(jacobians_match(left_jacobian_inverse_so3(w),
                                numerical_jacobian(f, VectorXd::Zero(3), 1e-6), 1e-7))
        << "w = " << w.transpose();
    EXPECT_LT((left_jacobian_so3(w) * left_jacobian_inverse_so3(w) - Matrix3d::Identity())
                  .cwiseAbs()
                  .maxCoeff(),
              1e-12)
        << "w = " << w.transpose();
  }
}

TEST(So3Jacobians, SeriesAndClosedFormsAgreeAtTheSwitch) {
  // Just below and above 1e-4 rad the two branches must give the same matrices to rounding.
  const Vector3d axis = Vector3d(1, -2, 0.5).normalized();
  const Vector3d below = 0.999999e-4 * axis, above = 1.000001e-4 * axis;
  EXPECT_LT((left_jacobian_so3(below) - left_jacobian_so3(above)).norm(), 1e-9);
  EXPECT_LT((left_jacobian_inverse_so3(below) - left_jacobian_inverse_so3(above)).norm(), 1e-9);
  EXPECT_EQ(left_jacobian_so3(Vector3d::Zero()), Matrix3d::Identity());
  EXPECT_EQ(left_jacobian_inverse_so3(Vector3d::Zero()), Matrix3d::Identity());
}

}  // namespace
}  // namespace kincal
