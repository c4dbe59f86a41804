#pragma once
// ISO 9283's pose statistics from held-out measurements that repeat commanded configurations
// (`kincal validate`; docs/calibrating-a-machine.md, "ISO 9283 statistics"). The standard's
// "command" is the pose the controller was asked for; here it is the calibrated model's
// prediction at the commanded actuator values, so that the figures say how well the model
// tells where the robot goes (accuracy) and how well the robot returns there (repeatability).
// For each commanded configuration measured n >= 2 times, of a sensor that measures a point
// (positions p_j, j = 1..n, predicted P):
//
//   barycentre      p̄ = (1/n) Σ p_j
//   accuracy        AP = |p̄ − P|                                   (and per axis, p̄ − P)
//   repeatability   RP = l̄ + 3 S_l,  l_j = |p_j − p̄|,  l̄ = (1/n) Σ l_j,
//                   S_l = sqrt(Σ (l_j − l̄)² / (n − 1))
//
// and for two commanded configurations measured the same number of times, cycle by cycle
// (the j-th measurement of one with the j-th of the other, in the file's order):
//
//   distance accuracy       AD = D̄ − D_c,  D_j = |p1_j − p2_j|,  D̄ = (1/n) Σ D_j,
//                           D_c = |P1 − P2|
//   distance repeatability  RD = 3 S_D,  S_D = sqrt(Σ (D_j − D̄)² / (n − 1))
//
// Consecutive repeated configurations (in the order they first appear) form the pairs.
//
// Orientation, for a sensor that measures one (a pose tracker: orientations R_j, predicted
// R_c): the standard's angles a, b, c about x, y, z are taken, for the small angles between
// repeats, as the components of rotation vectors in the sensor's axes (no Euler convention to
// choose, continuous at every attitude):
//
//   mean orientation   R̄: the rotation with Σ log(R_j R̄ᵀ) = 0 (iterated from R_1)
//   accuracy           (APa, APb, APc) = log(R̄ R_cᵀ)               (and its angle |.|)
//   repeatability      RPa = 3 S_a,  S_a = sqrt(Σ e_ja² / (n − 1)),  e_j = log(R_j R̄ᵀ)
//                      (likewise b, c; ISO writes ±3 S_a)

#include <nlohmann/json.hpp>
#include <string>
#include <vector>

#include "kincal/framework/calibration/calibration_problem.hpp"

namespace kincal {

struct Iso9283Pose {
  int first_row = 0;  ///< the row (0-based) of its first measurement
  int repeats = 0;
  Vector3d predicted = Vector3d::Zero();
  Vector3d barycentre = Vector3d::Zero();
  double accuracy = 0;       ///< AP, mm
  double repeatability = 0;  ///< RP, mm
  /// With an orientation (else empty): (APa, APb, APc) and (RPa, RPb, RPc), rad.
  bool has_orientation = false;
  Vector3d orientation_accuracy = Vector3d::Zero();
  Vector3d orientation_repeatability = Vector3d::Zero();
};

struct Iso9283Distance {
  int first = 0, second = 0;  ///< indices into Iso9283Stats::poses
  int repeats = 0;
  double commanded = 0;      ///< D_c, mm
  double accuracy = 0;       ///< AD, mm
  double repeatability = 0;  ///< RD, mm
};

struct Iso9283Stats {
  std::vector<Iso9283Pose> poses;
  std::vector<Iso9283Distance> distances;
  /// The largest AP and RP over the poses, AD (absolute) and RD over the pairs.
  double max_accuracy = 0, max_repeatability = 0, max_distance_accuracy = 0,
         max_distance_repeatability = 0;
  /// With an orientation: the largest angle |log(R̄ R_cᵀ)| and the largest RPa, RPb, RPc (rad).
  bool has_orientation = false;
  double max_orientation_accuracy = 0, max_orientation_repeatability = 0;
  bool computed() const { return !poses.empty(); }
};

/// The statistics of `data` (rows that repeat a configuration exactly) for the first sensor
/// of `model` that measures a point, at the parameter values `values`. Empty when no
/// configuration is measured twice or no sensor measures a point. Rows whose point was not
/// measured are left out.
Iso9283Stats iso9283_statistics(const MeasurementModel& model, const VectorXd& values,
                                const Measurements& data);

/// The text `kincal validate` prints: the summary and a line per pose (at most `shown`),
/// each named by the file line of its first measurement (`lines`; empty: the row from 1).
std::string iso9283_text(const Iso9283Stats& stats, const std::vector<int>& lines, int shown = 10);
/// {"max_ap_mm", "max_rp_mm", "max_ad_mm", "max_rd_mm", "poses": [{line, repeats,
///  predicted_mm, barycentre_mm, ap_mm, rp_mm}], "distances": [{first, second, repeats,
///  commanded_mm, ad_mm, rd_mm}]} (first, second: the poses' lines); with an orientation also
///  "max_ap_orientation_rad", "max_rp_orientation_rad" and per pose "ap_abc_rad",
///  "ap_orientation_rad" (the angle), "rp_abc_rad".
nlohmann::ordered_json iso9283_json(const Iso9283Stats& stats, const std::vector<int>& lines);

}  // namespace kincal
