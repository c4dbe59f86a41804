#pragma once
// The hand-eye equation A_k X = X B_k, solved in closed form: the starting value of a camera's
// or a tool's mount from pairs of motions seen from both sides (the robot's flange poses and a
// camera's views of a target). Rotation by Park and Martin's method (IEEE Trans. Robotics and
// Automation 10(5), 1994): with alpha_k = log R_A_k and beta_k = log R_B_k, the rotation R_X
// maximising sum alpha_k . R_X beta_k is R_X = (M^T M)^(-1/2) M^T for M = sum beta_k alpha_k^T
// (computed through the SVD of M, which also covers rank-deficient sums); translation by
// linear least squares on (R_A_k - I) t_X = R_X t_B_k - t_A_k. At least two motions whose
// rotation axes are not parallel determine X; motions of less than `min_rotation` are left
// out of the rotation (their axis is noise) but kept for the translation.

#include <string>
#include <vector>

#include "kincal/framework/kinematics/pose.hpp"

namespace kincal {

struct HandEyeSolution {
  bool ok = false;
  Pose X;
  /// Why there is no solution (fewer than two usable motions, parallel axes), when !ok.
  std::string reason;
  int motions_used = 0;  ///< motions whose rotation entered R_X
  /// How well X satisfies the motions: the RMS of the angle of (R_A R_X)^T R_X R_B (rad) and
  /// of |R_A t_X + t_A - R_X t_B - t_X| (the translations' unit).
  double rotation_rms = 0, translation_rms = 0;
};

/// Solves A_k X = X B_k for the motions (A[k], B[k]); A and B have the same length.
HandEyeSolution solve_hand_eye(const std::vector<Pose>& A, const std::vector<Pose>& B,
                               double min_rotation = 0.05);

}  // namespace kincal
