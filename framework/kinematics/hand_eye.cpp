#include "kincal/framework/kinematics/hand_eye.hpp"

#include <Eigen/SVD>
#include <cmath>
#include <stdexcept>

namespace kincal {

HandEyeSolution solve_hand_eye(const std::vector<Pose>& A, const std::vector<Pose>& B,
                               double min_rotation) {
  if (A.size() != B.size()) throw std::invalid_argument("solve_hand_eye: A and B differ in length");
  HandEyeSolution solution;
  Matrix3d M = Matrix3d::Zero();
  for (std::size_t k = 0; k < A.size(); ++k) {
    const Vector3d alpha = log_so3(A[k].rotation);
    const Vector3d beta = log_so3(B[k].rotation);
    if (alpha.norm() < min_rotation || beta.norm() < min_rotation) continue;
    M += beta * alpha.transpose();
    ++solution.motions_used;
  }
  if (solution.motions_used < 2) {
    solution.reason =
        "fewer than two motions turn by more than " + std::to_string(min_rotation) + " rad";
    return solution;
  }
  // R_X = (M^T M)^(-1/2) M^T = V U^T for M = U S V^T, with the sign that makes it a rotation.
  const Eigen::JacobiSVD<Matrix3d> svd(M, Eigen::ComputeFullU | Eigen::ComputeFullV);
  const Vector3d s = svd.singularValues();
  if (!(s[1] > 1e-6 * s[0])) {
    solution.reason =
        "the motions' rotation axes are all parallel: the mount's rotation about "
        "them is not determined";
    return solution;
  }
  Matrix3d V = svd.matrixV();
  if ((V * svd.matrixU().transpose()).determinant() < 0) V.col(2) = -V.col(2);
  const Matrix3d R = V * svd.matrixU().transpose();

  const Eigen::Index n = static_cast<Eigen::Index>(A.size());
  MatrixXd C(3 * n, 3);
  VectorXd d(3 * n);
  for (Eigen::Index k = 0; k < n; ++k) {
    const Pose& a = A[static_cast<std::size_t>(k)];
    const Pose& b = B[static_cast<std::size_t>(k)];
    C.middleRows<3>(3 * k) = a.rotation - Matrix3d::Identity();
    d.segment<3>(3 * k) = R * b.translation - a.translation;
  }
  const Eigen::JacobiSVD<MatrixXd> ls(C, Eigen::ComputeThinU | Eigen::ComputeThinV);
  const Vector3d sc = ls.singularValues();
  if (!(sc[2] > 1e-6 * sc[0])) {
    solution.reason =
        "the motions' rotation axes are all parallel: the mount's position along "
        "them is not determined";
    return solution;
  }
  solution.X.rotation = R;
  solution.X.translation = ls.solve(d);

  double angle2 = 0, distance2 = 0;
  for (std::size_t k = 0; k < A.size(); ++k) {
    const Pose left = compose(A[k], solution.X);
    const Pose right = compose(solution.X, B[k]);
    angle2 += log_so3(left.rotation.transpose() * right.rotation).squaredNorm();
    distance2 += (left.translation - right.translation).squaredNorm();
  }
  solution.rotation_rms = std::sqrt(angle2 / static_cast<double>(A.size()));
  solution.translation_rms = std::sqrt(distance2 / static_cast<double>(A.size()));
  solution.ok = true;
  return solution;
}

}  // namespace kincal
